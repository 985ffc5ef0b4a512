// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/resample.hpp"

#include "caustic/embree_mesh.hpp"

#include <algorithm>
#include <limits>

namespace caustic {

namespace {

// A face made ready for resampling at any grid size: its footprint in the
// flat face's frame and its triangles in Embree. Building the hierarchy is
// most of a level's cost, so a face's levels share one.
class FaceGrid {
 public:
  FaceGrid(const Mesh& mesh, const glm::dvec3& flat_normal)
      : mesh_(mesh), normal_(glm::normalize(flat_normal)), geometry_(mesh, identity_) {
    const auto basis = optics::basis_around(normal_);
    e1_ = basis.first, e2_ = basis.second;
    for (const glm::dvec3 p : mesh.positions) {
      const glm::dvec3 q(glm::dot(p, e1_), glm::dot(p, e2_), glm::dot(p, normal_));
      lo_ = glm::min(lo_, q);
      hi_ = glm::max(hi_, q);
    }
  }

  Mesh at(int n) const {
    if (n < 2) throw std::invalid_argument("resample_face needs at least 2 x 2 vertices");
    const double above = hi_.z + 1e-3 * (1 + hi_.z - lo_.z);
    // The outermost rays sit a hair inside the footprint, so edge vertices hit.
    const double shrink = 1e-6;
    Mesh out;
    std::vector<int> index(static_cast<std::size_t>(n) * n, -1);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double s = shrink + (1 - 2 * shrink) * i / (n - 1), t = shrink + (1 - 2 * shrink) * j / (n - 1);
        const glm::dvec3 origin =
            (lo_.x + s * (hi_.x - lo_.x)) * e1_ + (lo_.y + t * (hi_.y - lo_.y)) * e2_ + above * normal_;
        Geometry::Hit hit;
        if (!geometry_.intersect(origin, -normal_, 0.0, &hit)) continue;
        index[static_cast<std::size_t>(j) * n + i] = static_cast<int>(out.positions.size());
        out.positions.emplace_back(hit.point);
        out.normals.emplace_back(hit.normal);
        if (tinted(mesh_)) out.colours.emplace_back(glm::clamp(hit.tint, 0.0, 1.0));
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

 private:
  const Mesh& mesh_;
  const Placement identity_{};  // mesh coordinates; Geometry keeps a reference to it
  glm::dvec3 normal_, e1_{0.0}, e2_{0.0};
  glm::dvec3 lo_{std::numeric_limits<double>::infinity()}, hi_{-std::numeric_limits<double>::infinity()};
  Geometry geometry_;
};

}  // namespace

Mesh resample_face(const Mesh& mesh, const glm::dvec3& flat_normal, int n) {
  if (n < 2) throw std::invalid_argument("resample_face needs at least 2 x 2 vertices");
  return FaceGrid(mesh, flat_normal).at(n);
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
  if (std::any_of(resolutions.begin(), resolutions.end(), [](int n) { return n != 0; })) {
    const FaceGrid grid(*source, flat_normal);
    for (int n : resolutions)
      if (n != 0) levels.resampled[n] = std::make_shared<const Mesh>(grid.at(n));
  }
  levels.bounds = std::make_shared<const MeshBounds>(mesh_bounds(*source, flat_normal));
  levels.source = std::move(source);
  return levels;
}

}  // namespace caustic
