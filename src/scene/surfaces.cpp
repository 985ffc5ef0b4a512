// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/surfaces.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace caustic {

Mesh grid_mesh(const HeightField& surface, int nx, int ny) {
  if (nx < 2 || ny < 2) throw std::invalid_argument("grid_mesh needs at least 2 x 2 vertices");
  Mesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(nx) * ny);
  mesh.normals.reserve(mesh.positions.capacity());
  for (int j = 0; j < ny; ++j) {
    const double y = -surface.half_width_y + 2.0 * surface.half_width_y * j / (ny - 1);
    for (int i = 0; i < nx; ++i) {
      const double x = -surface.half_width_x + 2.0 * surface.half_width_x * i / (nx - 1);
      const glm::dvec2 g = surface.gradient(x, y);
      mesh.positions.emplace_back(x, y, surface.height(x, y));
      mesh.normals.emplace_back(glm::normalize(glm::dvec3(g.x, g.y, -1.0)));
    }
  }
  auto index = [nx](int i, int j) { return static_cast<unsigned>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      // (a, b=+y, c=+x) winds clockwise seen from +z: the face normal points to -z.
      mesh.triangles.emplace_back(index(i, j), index(i, j + 1), index(i + 1, j));
      mesh.triangles.emplace_back(index(i + 1, j), index(i, j + 1), index(i + 1, j + 1));
    }
  return mesh;
}

HeightField plano_convex_lens(double radius, double half_width) {
  if (!(half_width * std::sqrt(2.0) < radius)) throw std::invalid_argument("lens footprint exceeds its sphere");
  HeightField f;
  f.height = [radius](double x, double y) { return radius - std::sqrt(radius * radius - x * x - y * y); };
  f.gradient = [radius](double x, double y) {
    const double root = std::sqrt(radius * radius - x * x - y * y);
    return glm::dvec2(x / root, y / root);
  };
  f.half_width_x = f.half_width_y = half_width;
  return f;
}

HeightField cylindrical_lens(double radius, double half_width) {
  if (!(half_width < radius)) throw std::invalid_argument("lens footprint exceeds its cylinder");
  HeightField f;
  f.height = [radius](double x, double) { return radius - std::sqrt(radius * radius - x * x); };
  f.gradient = [radius](double x, double) { return glm::dvec2(x / std::sqrt(radius * radius - x * x), 0.0); };
  f.half_width_x = f.half_width_y = half_width;
  return f;
}

HeightField sine_window(double amplitude_x, double k_x, double amplitude_y, double k_y, double half_width) {
  HeightField f;
  f.height = [=](double x, double y) { return -amplitude_x * std::cos(k_x * x) - amplitude_y * std::cos(k_y * y); };
  f.gradient = [=](double x, double y) {
    return glm::dvec2(amplitude_x * k_x * std::sin(k_x * x), amplitude_y * k_y * std::sin(k_y * y));
  };
  f.half_width_x = f.half_width_y = half_width;
  return f;
}

HeightField flat_face(double half_width) {
  HeightField f;
  f.height = [](double, double) { return 0.0; };
  f.gradient = [](double, double) { return glm::dvec2(0.0); };
  f.half_width_x = f.half_width_y = half_width;
  return f;
}

HeightField wedge(double apex, double half_width_x, double half_width_y) {
  const double t = std::tan(apex);
  return {[t](double x, double) { return t * x; }, [t](double, double) { return glm::dvec2(t, 0); }, half_width_x,
          half_width_y};
}

namespace {

// Appends a triangle wound so that its geometric normal points along `outward`.
void add_oriented(Mesh& mesh, unsigned a, unsigned b, unsigned c, const glm::dvec3& outward) {
  const glm::dvec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
  if (glm::dot(glm::cross(pb - pa, pc - pa), outward) < 0) std::swap(b, c);
  mesh.triangles.emplace_back(a, b, c);
}

unsigned add_vertex(Mesh& mesh, const glm::dvec3& p, const glm::dvec3& n) {
  mesh.positions.emplace_back(p);
  mesh.normals.emplace_back(glm::normalize(n));
  return static_cast<unsigned>(mesh.positions.size() - 1);
}

}  // namespace

Mesh closed_body(const HeightField& upper, const HeightField& lower, int n) {
  if (n < 2) throw std::invalid_argument("closed_body needs at least 2 x 2 vertices a face");
  const double hx = upper.half_width_x, hy = upper.half_width_y;
  auto x_at = [&](int i) { return -hx + 2.0 * hx * i / (n - 1); };
  auto y_at = [&](int j) { return -hy + 2.0 * hy * j / (n - 1); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (!(upper.height(x_at(i), y_at(j)) > lower.height(x_at(i), y_at(j))))
        throw std::invalid_argument("closed_body: the lower face reaches the upper one");
  Mesh mesh;
  // The two faces: upper outward +z, lower outward -z.
  for (const int side : {+1, -1}) {
    const HeightField& f = side > 0 ? upper : lower;
    const unsigned base = static_cast<unsigned>(mesh.positions.size());
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const glm::dvec2 g = f.gradient(x_at(i), y_at(j));
        add_vertex(mesh, {x_at(i), y_at(j), f.height(x_at(i), y_at(j))}, static_cast<double>(side) * glm::dvec3(-g.x, -g.y, 1.0));
      }
    auto at = [&](int i, int j) { return base + static_cast<unsigned>(j * n + i); };
    const glm::dvec3 out(0.0, 0.0, static_cast<double>(side));
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        add_oriented(mesh, at(i, j), at(i + 1, j), at(i, j + 1), out);
        add_oriented(mesh, at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), out);
      }
  }
  // The walls: a strip of quads along each edge of the footprint.
  const struct {
    glm::dvec3 normal;
    bool along_y;
    double fixed;
  } walls[] = {{{-1, 0, 0}, true, -hx}, {{1, 0, 0}, true, hx}, {{0, -1, 0}, false, -hy}, {{0, 1, 0}, false, hy}};
  for (const auto& w : walls) {
    const unsigned base = static_cast<unsigned>(mesh.positions.size());
    for (int k = 0; k < n; ++k) {
      const double x = w.along_y ? w.fixed : x_at(k), y = w.along_y ? y_at(k) : w.fixed;
      add_vertex(mesh, {x, y, lower.height(x, y)}, w.normal);
      add_vertex(mesh, {x, y, upper.height(x, y)}, w.normal);
    }
    for (unsigned k = 0; k + 1 < static_cast<unsigned>(n); ++k) {
      const unsigned lo0 = base + 2 * k, hi0 = lo0 + 1, lo1 = lo0 + 2, hi1 = lo0 + 3;
      add_oriented(mesh, lo0, hi0, lo1, w.normal);
      add_oriented(mesh, lo1, hi0, hi1, w.normal);
    }
  }
  return mesh;
}

Mesh biconvex_lens(double r1, double r2, double centre_thickness, double half_width, int n) {
  // Lower face: the plano-convex cap turned over, apex at -d/2.
  HeightField up = plano_convex_lens(r1, half_width), down = plano_convex_lens(r2, half_width);
  const double half = centre_thickness / 2;
  HeightField upper{[=](double x, double y) { return half - up.height(x, y); },
                    [=](double x, double y) { return -up.gradient(x, y); }, half_width, half_width};
  HeightField lower{[=](double x, double y) { return -half + down.height(x, y); },
                    [=](double x, double y) { return down.gradient(x, y); }, half_width, half_width};
  return closed_body(upper, lower, n);
}

}  // namespace caustic
