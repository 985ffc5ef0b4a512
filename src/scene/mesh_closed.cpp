// SPDX-License-Identifier: LGPL-2.1-or-later
// Whether a mesh bounds a volume, for solids. Edges are matched by position,
// not index: a crease splits its vertices (one normal per face) without
// opening the surface.
#include "caustic/mesh.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <string>

namespace caustic {

void check_closed(const Mesh& mesh) {
  // One id per distinct position.
  std::map<std::array<float, 3>, unsigned> ids;
  std::vector<unsigned> id(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    id[i] = ids.emplace(std::array<float, 3>{p.x, p.y, p.z}, static_cast<unsigned>(ids.size())).first->second;
  }
  // Each undirected edge: +1 for a run from lower to higher id, -1 back.
  std::map<std::pair<unsigned, unsigned>, std::array<int, 2>> edges;  // {uses, net direction}
  double volume = 0;
  for (const auto& t : mesh.triangles) {
    const unsigned v[3] = {id[t.x], id[t.y], id[t.z]};
    for (int k = 0; k < 3; ++k) {
      const unsigned a = v[k], b = v[(k + 1) % 3];
      auto& e = edges[{std::min(a, b), std::max(a, b)}];
      ++e[0];
      e[1] += a < b ? 1 : -1;
    }
    const glm::dvec3 p0 = mesh.positions[t.x], p1 = mesh.positions[t.y], p2 = mesh.positions[t.z];
    volume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;  // divergence theorem, outward winding positive
  }
  std::size_t open = 0;
  for (const auto& [edge, e] : edges)
    if (e[0] != 2 || e[1] != 0) ++open;
  if (open > 0)
    throw SceneError("mesh", "a solid must be a closed surface: " + std::to_string(open) +
                                 " edges are not shared by exactly two triangles wound the same way round");
  if (!(volume > 0))
    throw SceneError("mesh", "a solid's triangles must be wound outward (counter-clockwise seen from outside); "
                             "this one encloses a negative volume");
}

}  // namespace caustic
