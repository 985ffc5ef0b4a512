// SPDX-License-Identifier: LGPL-2.1-or-later
// The freeform face as a mesh: resampling the warped transport grid onto a
// regular lens grid, the triangle mesh with explicit normals, and the
// watertight solid a workshop can mill.
#pragma once

#include "heights.hpp"

#include "caustic/design_solid.hpp"

#include "caustic/mesh.hpp"

namespace caustic::design {

/// Moves the grid's vertices onto the regular w x w lattice spanning the
/// same square, interpolating screen point and height linearly over the
/// warped triangles (split like the face mesh). Regular points that no
/// unfolded triangle covers (only where the map folds) take the values of the
/// nearest covered point along their row, then column. The slopes are left
/// for refine_heights to recompute.
FaceGrid resample_regular(const FaceGrid& warped, double size);

/// Triangles of a w x w vertex grid, counter-clockwise seen from +z, the
/// diagonals mirrored between the four quadrants.
std::vector<glm::uvec3> grid_triangles(int w);

/// The face in millimetres with unit normals (-G, 1) / |(-G, 1)|, pointing
/// up into the glass (orientation is free for the renderers).
Mesh face_mesh(const FaceGrid& grid);

}  // namespace caustic::design
