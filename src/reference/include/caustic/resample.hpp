// Resamples a caustic face on a regular grid: the same surface at another
// vertex count, for comparing mesh resolutions (and for coarser levels of
// detail) without moving the focus, as a decimation would.
#pragma once

#include "caustic/mesh.hpp"

namespace caustic {

/// Casts an n x n grid of rays along -flat_normal (mesh coordinates) over
/// the face's footprint and keeps each hit's position and interpolated
/// normal; grid points outside the face are left out with their triangles.
/// Throws std::invalid_argument for n < 2 and SceneError when nothing is hit.
Mesh resample_face(const Mesh& mesh, const glm::dvec3& flat_normal, int n);

}  // namespace caustic
