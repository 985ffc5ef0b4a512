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
#include <vector>

namespace caustic {

struct TriangleCounts {
  std::uint32_t drawn = 0, dropped = 0, positive = 0, negative = 0, collapsed = 0;
};

/// The per-vertex method's rays for every vertex of `mesh` (placed by
/// `placement`), refracted with index `ior`, in the form the multipass
/// tracer lands its rays (caustic/light_grid.hpp).
std::vector<LandedVertex> land_vertices(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior);

/// Sets up the triangles over `rays` as caustic.geom does and adds their
/// irradiance times `weight` (and their tint when `raster` has three
/// channels) into `raster`, whose size is the target's, as caustic.frag
/// does; counts the triangles into `counts` when it is not null. A share of
/// the triangles a core, each into a layer of its own (it sets the
/// raster's mesh); the caller flushes or resolves the raster.
void deposit_on_cpu(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles,
                    const Scene& scene, const Placement& placement, glm::dvec3 weight, CoverageRaster* raster,
                    TriangleCounts* counts);

}  // namespace caustic
