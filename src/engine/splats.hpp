// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic pass's per-vertex and per-triangle work on the CPU: the twin
// of caustic.vert and caustic.geom, for renderers that run those stages
// slowly. A software rasteriser (llvmpipe) runs the vertex and geometry
// stages on one thread, about 1.4 us a triangle here, while it spreads the
// fragment stage over every core; on the CPU, in double precision, the same
// setup is a tenth of that, and the GL is left one instanced quad a
// triangle (caustic_splat.vert) and the unchanged exact-coverage fragment
// stage. Tests hold the two paths' pictures and counts against each other.
#pragma once

#include "caustic/light_grid.hpp"
#include "caustic/mesh.hpp"
#include "caustic/receivers.hpp"

#include <cstdint>
#include <vector>

namespace caustic {

struct TriangleCounts {
  std::uint32_t drawn = 0, dropped = 0, positive = 0, negative = 0, collapsed = 0;
};

/// What caustic.geom hands caustic.frag, for one square of pixels: the
/// triangle's corners in window pixels, its irradiance and tint. A triangle
/// is drawn as the squares that tile its pixel-aligned bounding box, each a
/// GL point (one primitive, where a quad is two), at most `max_side` pixels
/// wide: squares past the triangle add exact coverage 0. 64 bytes, one
/// vertex of caustic_splat.vert.
struct Splat {
  glm::vec2 a{0.0f}, b{0.0f};
  glm::vec2 c{0.0f}, lo{0.0f};  ///< lo: the square's lowest pixel corner
  float side = 1;               ///< pixels
  float irradiance = 0;
  float point = 0;  ///< 1: collapsed to a point, all flux to one pixel
  float unused = 0;
  glm::vec3 tint{1.0f};
  float unused2 = 0;
};
static_assert(sizeof(Splat) == 16 * sizeof(float));

/// The per-vertex method's rays for every vertex of `mesh` (placed by
/// `placement`), refracted with index `ior`, in the form the multipass
/// tracer lands its rays (caustic/light_grid.hpp).
std::vector<LandedVertex> land_vertices(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior);

/// Sets up the triangles over `rays` on a `width` x `height` target as
/// caustic.geom does, putting their squares (at most `max_side` pixels, the
/// GL's largest point) in `splats` (cleared first) and counting the
/// triangles into `counts` when it is not null.
void make_splats(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles, const Scene& scene,
                 const Placement& placement, int width, int height, int max_side, std::vector<Splat>* splats,
                 TriangleCounts* counts);

}  // namespace caustic
