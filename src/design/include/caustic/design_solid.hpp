// SPDX-License-Identifier: LGPL-2.1-or-later
// The solid a workshop mills: the designed face closed by side walls and the
// flat face into one watertight slab.
#pragma once

#include "caustic/design.hpp"
#include "caustic/mesh.hpp"

#include <filesystem>

namespace caustic::design {

/// Closed slab: the face, side walls up to z = top and the flat top (a fan
/// around its centre). Outward winding, every edge shared by two triangles.
Mesh solid_mesh(const FaceGrid& grid, double top);

/// Signed volume of a closed triangle mesh (divergence theorem).
double mesh_volume(const Mesh& mesh);

/// Writes an OBJ with `v` and `f` lines only (positions shared by index, so
/// the file stays watertight for CAM software).
void write_solid_obj(const Mesh& mesh, const std::filesystem::path& file);

}  // namespace caustic::design
