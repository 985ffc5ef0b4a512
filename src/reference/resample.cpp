// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/resample.hpp"

#include "caustic/embree_mesh.hpp"

#include <limits>

namespace caustic {

Mesh resample_face(const Mesh& mesh, const glm::dvec3& flat_normal, int n) {
  if (n < 2) throw std::invalid_argument("resample_face needs at least 2 x 2 vertices");
  const glm::dvec3 normal = glm::normalize(flat_normal);
  const auto [e1, e2] = optics::basis_around(normal);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3 p : mesh.positions) {
    const glm::dvec3 q(glm::dot(p, e1), glm::dot(p, e2), glm::dot(p, normal));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const Placement identity;  // mesh coordinates
  const Geometry geometry(mesh, identity);
  const double above = hi.z + 1e-3 * (1 + hi.z - lo.z);
  // The outermost rays sit a hair inside the footprint, so edge vertices hit.
  const double shrink = 1e-6;
  Mesh out;
  std::vector<int> index(static_cast<std::size_t>(n) * n, -1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double s = shrink + (1 - 2 * shrink) * i / (n - 1), t = shrink + (1 - 2 * shrink) * j / (n - 1);
      const glm::dvec3 origin = (lo.x + s * (hi.x - lo.x)) * e1 + (lo.y + t * (hi.y - lo.y)) * e2 + above * normal;
      Geometry::Hit hit;
      if (!geometry.intersect(origin, -normal, 0.0, &hit)) continue;
      index[static_cast<std::size_t>(j) * n + i] = static_cast<int>(out.positions.size());
      out.positions.emplace_back(hit.point);
      out.normals.emplace_back(hit.normal);
      if (tinted(mesh)) out.colours.emplace_back(glm::clamp(hit.tint, 0.0, 1.0));
    }
  auto at = [&](int i, int j) { return index[static_cast<std::size_t>(j) * n + i]; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = at(i, j), b = at(i, j + 1), c = at(i + 1, j), d = at(i + 1, j + 1);
      if (a >= 0 && b >= 0 && c >= 0) out.triangles.emplace_back(a, b, c);
      if (c >= 0 && b >= 0 && d >= 0) out.triangles.emplace_back(c, b, d);
    }
  if (out.triangles.empty()) throw SceneError("mesh", "resampling hit no part of the face");
  return out;
}

std::vector<int> coarser_resolutions(const Mesh& source, const Scene& scene) {
  std::vector<int> out;
  if (scene.object.shape == Shape::solid || scene.water) return out;
  for (int n = 8; static_cast<std::size_t>(n) * n < source.positions.size() && n <= 1024; n *= 2) out.push_back(n);
  return out;
}

MeshLevels build_mesh_levels(std::shared_ptr<const Mesh> source, const glm::dvec3& flat_normal,
                             const std::vector<int>& resolutions) {
  MeshLevels levels;
  for (int n : resolutions)
    if (n != 0) levels.resampled[n] = std::make_shared<const Mesh>(resample_face(*source, flat_normal, n));
  levels.bounds = std::make_shared<const MeshBounds>(mesh_bounds(*source, flat_normal));
  levels.source = std::move(source);
  return levels;
}

}  // namespace caustic
