// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic pass's per-vertex and per-triangle work on the CPU: the twin
// of caustic.vert, caustic.geom and caustic.frag, for renderers that run
// those stages slowly. A software rasteriser (llvmpipe) runs the vertex and
// geometry stages on one thread, about 1.4 us a triangle here, and its
// fragment stage pays the exact coverage over each triangle's whole box;
// on the CPU, in double precision, the setup is a tenth of that and the
// coverage (coverage.hpp) is paid per edge, leaving the GL one image to
// add. Tests hold the two paths' pictures and counts against each other.
#pragma once

#include "caustic/light_grid.hpp"
#include "coverage.hpp"
#include "caustic/mesh.hpp"
#include "caustic/receivers.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace caustic {

struct TriangleCounts {
  std::uint32_t drawn = 0, dropped = 0, positive = 0, negative = 0, collapsed = 0;
};

/// The per-vertex method's rays for every vertex of `mesh` (placed by
/// `placement`), refracted with index `ior`, in the form the multipass
/// tracer lands its rays (caustic/light_grid.hpp).
std::vector<LandedVertex> land_vertices(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior);

/// The ray through the point of triangle `t` at barycentric weights `uv`
/// of its second and third corners, landed as its corners were.
using PartedRays = std::function<LandedVertex(std::size_t t, glm::dvec2 uv)>;

/// The per-vertex method's rays inside `mesh`'s triangles: position, normal
/// and tint interpolated between the corners, as the method models the
/// face between its vertices. Holds references to its arguments.
PartedRays parted_rays(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior);

/// Sets up the triangles over `rays` as caustic.geom does and adds their
/// irradiance times `weight` (and their tint when `raster` has three
/// channels) into `raster`, whose size is the target's, as caustic.frag
/// does; counts the triangles into `counts` when it is not null. A share of
/// the triangles a core, each into a layer of its own (it sets the
/// raster's mesh); the caller flushes or resolves the raster. A triangle
/// whose corners parted among the surfaces (an occluder's outline, a
/// lathe's silhouette or seam) leaves a third of its flux at each corner
/// that landed, as caustic.geom does; with `parted`, it is cut into four,
/// twice where its pieces still part, each piece whose corners land
/// together spread whole and each smallest one that parts left where the
/// ray through its centroid lands, so the outline's error shrinks with the
/// pieces' size and no dots are left between them.
void deposit_on_cpu(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles,
                    const Scene& scene, const Placement& placement, glm::dvec3 weight, CoverageRaster* raster,
                    TriangleCounts* counts, const PartedRays* parted = nullptr);

}  // namespace caustic
