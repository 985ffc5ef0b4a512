// SPDX-License-Identifier: LGPL-2.1-or-later
// The multipass method (docs/physics.md §12): a regular grid of rays from
// the light, each followed through a solid by follow_solid (FresnelSplit::
// weight) to the screen plane. Neighbouring rays that took the same branch
// (equal signatures) span a triangle whose flux the engine spreads over the
// screen with the exact-coverage splat of the per-vertex method. A triangle
// whose corners parted (a crease, the rim, TIR on some of them) is sampled
// by 16 more rays, each leaving a sixteenth of its flux where it lands, as
// a point: the parted strip is one grid cell wide, so its error falls as
// the square of the grid's spacing instead of in proportion to it.
#pragma once

#include "caustic/launch.hpp"
#include "caustic/solid_path.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace caustic {

/// One grid ray as the engine's deposit reads it (the layout of
/// shaders/caustic_landed.vert's attributes).
struct LandedVertex {
  glm::vec2 screen{0.0f};    ///< hit on its surface, (right, up) from the surface's centre, world units
  glm::vec2 plane{0.0f};     ///< hit on the "report" mode's plane behind the screen
  glm::vec3 footprint{0.0f}; ///< the ray's start on the launch rectangle (world)
  float transmittance = 1;   ///< Fresnel weights along the path (1 with Fresnel off)
  float valid = 0;           ///< 1: left the solid toward the screen plane
  glm::vec3 tint{1.0f};
  float share = 1;           ///< of its triangle's flux this vertex's triangle carries
  float surface = -1;        ///< the surface it landed on (caustic/receivers.hpp); -1: none
  std::int32_t element = -1; ///< a lathe's triangle it landed on (ReceiverHit::element); not in the shaders
};

struct LandedGrid {
  std::vector<LandedVertex> vertices;
  std::vector<glm::uvec3> triangles;
  std::size_t split = 0;  ///< grid triangles whose corners took different branches
  std::size_t rays = 0;   ///< rays traced, the parted triangles' samples included
};

/// Rays a parted triangle is sampled by: the centroids of its subdivision
/// into 4 x 4 equal triangles, each as barycentric weights (u, v) of its
/// second and third corners. Each carries a sixteenth of the flux.
constexpr int kPartedSamples = 16;
std::array<glm::dvec2, kPartedSamples> parted_samples();

/// Traces an n x n grid (n >= 2) over the launch rectangle of `solid`
/// through index `ior`, on `threads` threads (0: all cores).
LandedGrid trace_light_grid(const Scene& scene, const Solid& solid, double ior, int n, int threads = 0);

}  // namespace caustic
