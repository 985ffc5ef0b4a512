// SPDX-License-Identifier: LGPL-2.1-or-later
// A slab's caustic face must be a height field over its flat face: every
// point of the flat face lies above one point of the caustic face. The
// per-vertex method gives each triangle the light through its footprint
// on the flat face, so a face whose triangles overlap there (a layer
// written twice, two sheets stacked, a fold) drew twice the light that
// crossed the glass, where the reference tracer, which meets the first
// surface only, drew it once. Checked once, when a face is loaded, since
// the face and its flat face's normal are the scene's and never a
// viewer's to change.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <glm/glm.hpp>

namespace caustic {

/// Throws SceneError("mesh") when two triangles of `mesh` cover one point
/// seen along `normal` (model space): sampled on a grid of about four
/// points a triangle, so an overlap narrower than that spacing may pass.
void check_height_field(const Mesh& mesh, const glm::dvec3& normal);

/// The scene's caustic face from its OBJ file (load_obj), checked with
/// check_height_field along object.flat_face_normal unless the object is
/// a solid (whose faces are checked as a closed surface instead).
Mesh load_face(const Scene& scene);

}  // namespace caustic
