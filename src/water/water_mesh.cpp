// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/water_mesh.hpp"

#include <glm/glm.hpp>

namespace caustic::water {

Mesh water_mesh(const WaveSolver& solver) {
  const auto& p = solver.params();
  const int n = p.grid;
  const double dx = spacing(p), half = p.size / 2;
  const auto& h = solver.heights();
  const auto at = [&](int i, int j) { return h[static_cast<std::size_t>(j) * n + i]; };
  Mesh mesh;
  const auto count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  mesh.positions.reserve(count);
  mesh.normals.reserve(count);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.positions.emplace_back(-half + i * dx, -half + j * dx, at(i, j));
      // A wall's ghost mirrors the row inside: the difference across it is zero.
      const double hx = (at(mirrored(i + 1, n), j) - at(mirrored(i - 1, n), j)) / (2 * dx);
      const double hy = (at(i, mirrored(j + 1, n)) - at(i, mirrored(j - 1, n))) / (2 * dx);
      mesh.normals.emplace_back(glm::normalize(glm::dvec3(-hx, -hy, 1.0)));
    }
  mesh.triangles.reserve(2 * static_cast<std::size_t>(n - 1) * static_cast<std::size_t>(n - 1));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto v = static_cast<unsigned>(j * n + i), un = static_cast<unsigned>(n);
      mesh.triangles.emplace_back(v, v + 1, v + un + 1);
      mesh.triangles.emplace_back(v, v + un + 1, v + un);
    }
  return mesh;
}

}  // namespace caustic::water
