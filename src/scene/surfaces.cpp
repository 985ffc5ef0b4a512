// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/surfaces.hpp"

#include <cmath>
#include <stdexcept>

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

}  // namespace caustic
