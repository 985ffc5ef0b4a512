// SPDX-License-Identifier: LGPL-2.1-or-later
// The water's surface as the engine draws it: a caustic face of shape
// "surface" (caustic/scene.hpp), one vertex per grid point.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/wave_solver.hpp"

namespace caustic::water {

/// Vertices at (x, y, h) with the pool centred on the origin and the still
/// level at z = 0, normals (-dh/dx, -dh/dy, 1) normalised from central
/// differences (at a wall the mirrored row makes the slope across it zero,
/// as the solver's walls do), two triangles per grid cell wound
/// counter-clockwise seen from +z.
///
/// With `stride` above 1 (at most grid - 1), only every stride-th post per
/// side and the wall's, so that the mesh still spans the pool (the last cell
/// may be narrower): for a preview that draws its caustic at 1/stride of the
/// size, a quarter of the triangles at 2. Each normal is the full grid's at
/// its post, so the slopes are the water's; waves shorter than two of the
/// thinned cells are lost.
Mesh water_mesh(const WaveSolver& solver, int stride = 1);

}  // namespace caustic::water
