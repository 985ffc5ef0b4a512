// SPDX-License-Identifier: LGPL-2.1-or-later
#include "face.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace caustic::design {

std::vector<glm::uvec3> grid_triangles(int w) {
  std::vector<glm::uvec3> tris;
  tris.reserve(std::size_t(w - 1) * (w - 1) * 2);
  for (int j = 0; j + 1 < w; ++j)
    for (int i = 0; i + 1 < w; ++i) {
      const unsigned v00 = j * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      // Diagonals mirrored between the quadrants ("union jack"): the mesh is
      // symmetric under x -> -x and y -> -y, so symmetric targets give
      // symmetric faces after interpolation over the triangles.
      const bool left = 2 * i + 1 < w - 1, bottom = 2 * j + 1 < w - 1;
      if (left == bottom) {
        tris.push_back({v00, v10, v11});
        tris.push_back({v00, v11, v01});
      } else {
        tris.push_back({v00, v10, v01});
        tris.push_back({v10, v11, v01});
      }
    }
  return tris;
}

FaceGrid resample_regular(const FaceGrid& warped, double size) {
  const int w = warped.w;
  const double step = size / (w - 1), lo = -0.5 * size;
  FaceGrid out;
  out.w = w;
  out.lens.resize(warped.lens.size());
  out.screen.assign(warped.lens.size(), glm::dvec2(std::numeric_limits<double>::quiet_NaN()));
  out.height.assign(warped.lens.size(), 0.0);
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) out.lens[std::size_t(j) * w + i] = {lo + i * step, lo + j * step};
  // Rasterise every warped triangle over the lattice points in its bounding box.
  for (const auto& t : grid_triangles(w)) {
    const glm::dvec2 a = warped.lens[t.x], b = warped.lens[t.y], c = warped.lens[t.z];
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (!(det > 0)) continue;  // folded or collapsed: leave it to its neighbours
    const auto index = [&](double v) { return (v - lo) / step; };
    const int i0 = std::max(0, int(std::floor(index(std::min({a.x, b.x, c.x}))))),
              i1 = std::min(w - 1, int(std::ceil(index(std::max({a.x, b.x, c.x}))))),
              j0 = std::max(0, int(std::floor(index(std::min({a.y, b.y, c.y}))))),
              j1 = std::min(w - 1, int(std::ceil(index(std::max({a.y, b.y, c.y})))));
    const double eps = -1e-9 * det;  // points on shared edges belong to both sides
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t v = std::size_t(j) * w + i;
        if (!std::isnan(out.screen[v].x)) continue;
        const glm::dvec2 p = out.lens[v];
        const double wb = (p.x - a.x) * (c.y - a.y) - (c.x - a.x) * (p.y - a.y);
        const double wc = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);
        const double wa = det - wb - wc;
        if (wa < eps || wb < eps || wc < eps) continue;
        out.screen[v] = (wa * warped.screen[t.x] + wb * warped.screen[t.y] + wc * warped.screen[t.z]) / det;
        out.height[v] = (wa * warped.height[t.x] + wb * warped.height[t.y] + wc * warped.height[t.z]) / det;
      }
  }
  // Holes (folds only): copy the nearest covered value along the row, then the column.
  const auto fill = [&](bool rows) {
    for (int a = 0; a < w; ++a) {
      int last = -1;
      for (int b = 0; b < w; ++b) {
        const std::size_t v = rows ? std::size_t(a) * w + b : std::size_t(b) * w + a;
        if (!std::isnan(out.screen[v].x)) {
          for (int k = last + 1; k < b; ++k) {
            const std::size_t u = rows ? std::size_t(a) * w + k : std::size_t(k) * w + a;
            out.screen[u] = out.screen[v], out.height[u] = out.height[v];
          }
          last = b;
        }
      }
      if (last >= 0)
        for (int k = last + 1; k < w; ++k) {
          const std::size_t u = rows ? std::size_t(a) * w + k : std::size_t(k) * w + a;
          const std::size_t v = rows ? std::size_t(a) * w + last : std::size_t(last) * w + a;
          out.screen[u] = out.screen[v], out.height[u] = out.height[v];
        }
    }
  };
  fill(true);
  fill(false);
  for (const auto& s : out.screen)
    if (std::isnan(s.x)) throw std::runtime_error("the transport map covers no part of the lens grid");
  return out;
}

Mesh face_mesh(const FaceGrid& grid) {
  Mesh m;
  m.positions.reserve(grid.lens.size());
  m.normals.reserve(grid.lens.size());
  for (std::size_t v = 0; v < grid.lens.size(); ++v) {
    m.positions.emplace_back(grid.lens[v].x, grid.lens[v].y, grid.height[v]);
    m.normals.emplace_back(glm::normalize(glm::dvec3(-grid.slope[v], 1.0)));
  }
  m.triangles = grid_triangles(grid.w);
  return m;
}

Mesh solid_mesh(const FaceGrid& grid, double top) {
  const int w = grid.w;
  Mesh m;
  for (std::size_t v = 0; v < grid.lens.size(); ++v) m.positions.emplace_back(grid.lens[v].x, grid.lens[v].y, grid.height[v]);
  // The face is the bottom: outward is -z, so its triangles are reversed.
  for (const auto& t : grid_triangles(w)) m.triangles.push_back({t.x, t.z, t.y});
  // Border loop counter-clockwise seen from +z.
  std::vector<unsigned> loop;
  for (int i = 0; i < w - 1; ++i) loop.push_back(i);
  for (int j = 0; j < w - 1; ++j) loop.push_back(j * w + w - 1);
  for (int i = w - 1; i > 0; --i) loop.push_back((w - 1) * w + i);
  for (int j = w - 1; j > 0; --j) loop.push_back(j * w);
  const unsigned first_top = static_cast<unsigned>(m.positions.size());
  for (unsigned v : loop) m.positions.emplace_back(m.positions[v].x, m.positions[v].y, top);
  const unsigned centre = static_cast<unsigned>(m.positions.size());
  m.positions.emplace_back(0.5f * (m.positions[0].x + m.positions[loop[w - 1 + w - 1]].x),
                           0.5f * (m.positions[0].y + m.positions[loop[w - 1 + w - 1]].y), top);
  const unsigned count = static_cast<unsigned>(loop.size());
  for (unsigned k = 0; k < count; ++k) {
    const unsigned a = loop[k], b = loop[(k + 1) % count];
    const unsigned ta = first_top + k, tb = first_top + (k + 1) % count;
    // Wall quad a -> b -> tb -> ta faces outward for a counter-clockwise loop.
    m.triangles.push_back({a, b, tb});
    m.triangles.push_back({a, tb, ta});
    m.triangles.push_back({ta, tb, centre});
  }
  m.normals = smooth_normals(m.positions, m.triangles);
  return m;
}

double mesh_volume(const Mesh& mesh) {
  double v = 0;
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v;
}

void write_solid_obj(const Mesh& mesh, const std::filesystem::path& file) {
  std::FILE* f = std::fopen(file.c_str(), "w");
  if (!f) throw std::runtime_error(file.string() + ": cannot open for writing");
  std::fprintf(f, "# causticd designed solid, millimetres\n");
  for (const auto& p : mesh.positions) std::fprintf(f, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
  for (const auto& t : mesh.triangles) std::fprintf(f, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(file.string() + ": write failed");
}

}  // namespace caustic::design
