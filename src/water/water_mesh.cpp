// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/water_mesh.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <vector>

namespace caustic::water {

Mesh water_mesh(const WaveSolver& solver, int stride) {
  const auto& p = solver.params();
  const int n = p.grid;
  stride = std::clamp(stride, 1, n - 1);
  // The posts kept along each side: every stride-th, then the wall's.
  std::vector<int> posts;
  for (int i = 0; i < n - 1; i += stride) posts.push_back(i);
  posts.push_back(n - 1);
  const int m = static_cast<int>(posts.size());
  const double dx = spacing(p), half = p.size / 2;
  const auto& h = solver.heights();
  const auto at = [&](int i, int j) { return h[static_cast<std::size_t>(j) * n + i]; };
  Mesh mesh;
  const auto count = static_cast<std::size_t>(m) * static_cast<std::size_t>(m);
  mesh.positions.reserve(count);
  mesh.normals.reserve(count);
  for (const int j : posts)
    for (const int i : posts) {
      mesh.positions.emplace_back(-half + i * dx, -half + j * dx, at(i, j));
      // A wall's ghost mirrors the row inside: the difference across it is zero.
      const double hx = (at(mirrored(i + 1, n), j) - at(mirrored(i - 1, n), j)) / (2 * dx);
      const double hy = (at(i, mirrored(j + 1, n)) - at(i, mirrored(j - 1, n))) / (2 * dx);
      mesh.normals.emplace_back(glm::normalize(glm::dvec3(-hx, -hy, 1.0)));
    }
  mesh.triangles.reserve(2 * static_cast<std::size_t>(m - 1) * static_cast<std::size_t>(m - 1));
  for (int j = 0; j + 1 < m; ++j)
    for (int i = 0; i + 1 < m; ++i) {
      const auto v = static_cast<unsigned>(j * m + i), um = static_cast<unsigned>(m);
      mesh.triangles.emplace_back(v, v + 1, v + um + 1);
      mesh.triangles.emplace_back(v, v + um + 1, v + um);
    }
  return mesh;
}

}  // namespace caustic::water
