// SPDX-License-Identifier: LGPL-2.1-or-later
// Light through a closed glass body (object.shape "solid"): every face is an
// interface between air and glass, met in whatever order the ray meets them
// (docs/physics.md §12). Which side a hit is on comes from the triangle's
// winding (outward), the refraction from the interpolated vertex normal.
//
// At each interface the light splits into a refracted and a reflected part
// (Fresnel). Two ways of following that split:
// - weight: follow the refracted part with its transmittance as a weight and
//   drop the reflected one, except under TIR, which is followed whole. The
//   deterministic path of the multipass method; what it drops first reaches
//   the screen after two internal reflections, R^2 of the flux (0.16% at
//   normal incidence for n = 1.5).
// - sample: choose refraction with probability T, reflection otherwise,
//   flux unchanged (Russian roulette): the photon reference, exact on average.
// Without Fresnel every interface refracts (TIR still reflects), in both.
#pragma once

#include "caustic/embree_mesh.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace caustic {

/// More interface crossings than any sensible ray makes; a ray trapped
/// longer (TIR round a ring) is dropped, so every trace terminates.
inline constexpr int kMaxSolidEvents = 64;

enum class FresnelSplit { weight, sample };

/// The solid in Embree plus its smooth surfaces: triangles that share
/// vertices belong to one surface (a crease needs its own vertices, as a
/// closed_body or an OBJ with per-face normals gives it).
class Solid {
 public:
  /// `mesh` must outlive the Solid; the placement is copied.
  Solid(const Mesh& mesh, const Placement& placement);
  const Geometry& geometry() const { return geometry_; }
  int surface(unsigned triangle) const { return surface_[triangle]; }
  int surfaces() const { return surfaces_; }
  /// Half the world-space diagonal of the mesh's bounds: the scale of
  /// the nudge that keeps a ray off the face it leaves.
  double extent() const { return extent_; }
  /// The mesh's vertices in the world: what a launch rectangle must cover.
  const std::vector<glm::dvec3>& points() const { return points_; }
  glm::dvec3 centre() const { return centre_; }

 private:
  Placement placement_;  // before geometry_, which refers to it
  Geometry geometry_;
  std::vector<glm::dvec3> points_;
  glm::dvec3 centre_{0.0};
  std::vector<int> surface_;
  int surfaces_ = 0;
  double extent_ = 1;
};

/// Where the light leaves the solid, and what it met on the way.
struct SolidPath {
  bool valid = false;          ///< false: missed the solid, or trapped past kMaxSolidEvents
  glm::dvec3 origin{0.0}, dir{0.0};  ///< the last exit point and direction
  double transmittance = 1.0;  ///< product of the weights (FresnelSplit::weight)
  glm::dvec3 tint{1.0};        ///< product of the tints at every crossing
  std::uint64_t signature = 0; ///< the surfaces met and how: equal for rays on one smooth branch
  int events = 0;              ///< interfaces met
};

/// Follows a ray from `origin` along `dir` (unit) through `solid` with index
/// `ior`; `rng` is used (and needed) only by FresnelSplit::sample with Fresnel on.
SolidPath follow_solid(const Solid& solid, glm::dvec3 origin, glm::dvec3 dir, double ior, bool fresnel,
                       FresnelSplit split, std::mt19937_64* rng = nullptr);

}  // namespace caustic
