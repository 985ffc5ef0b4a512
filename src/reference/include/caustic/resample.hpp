// SPDX-License-Identifier: LGPL-2.1-or-later
// Resamples a caustic face on a regular grid: the same surface at another
// vertex count, for comparing mesh resolutions (and for coarser levels of
// detail) without moving the focus, as a decimation would.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/mesh_levels.hpp"

#include <memory>
#include <vector>

namespace caustic {

/// Casts an n x n grid of rays along -flat_normal (mesh coordinates) over
/// the face's footprint and keeps each hit's position and interpolated
/// normal (and colour, when tinted); grid points outside the face are left
/// out with their triangles.
/// Throws std::invalid_argument for n < 2 and SceneError when nothing is hit.
Mesh resample_face(const Mesh& mesh, const glm::dvec3& flat_normal, int n);

/// Grid sizes worth offering below a scene's mesh: powers of two from 8
/// while the grid has fewer vertices than the mesh itself; none for a solid,
/// which is no height field (its multipass tracer thins the light's grid
/// instead), nor for water, whose surface is new every frame (water.grid
/// sets its size).
std::vector<int> coarser_resolutions(const Mesh& source, const Scene& scene);

/// Resamples `source` (mesh coordinates, flat face normal `flat_normal`) at
/// each resolution. Throws SceneError when the face cannot be resampled.
MeshLevels build_mesh_levels(std::shared_ptr<const Mesh> source, const glm::dvec3& flat_normal,
                             const std::vector<int>& resolutions);

}  // namespace caustic
