// SPDX-License-Identifier: LGPL-2.1-or-later
// A caustic face at several vertex counts: the mesh as loaded plus the same
// surface resampled on coarser regular grids (built by build_mesh_levels in
// caustic/resample.hpp), so a cheaper level keeps the focus where the full
// mesh has it.
#pragma once

#include "caustic/mesh.hpp"

#include <map>
#include <memory>
#include <vector>

namespace caustic {

struct MeshLevels {
  std::shared_ptr<const Mesh> source;                      ///< as loaded: mesh_resolution 0
  std::map<int, std::shared_ptr<const Mesh>> resampled;    ///< n -> n x n grid
  /// The source's bounds about its flat-face normal, when known: placing
  /// the object for every answer then skips the pass over the vertices.
  std::shared_ptr<const MeshBounds> bounds;

  /// place_object on the source mesh, from `bounds` when they fit.
  Placement place(const ObjectParams& object) const;

  /// The mesh for `render.mesh_resolution`; throws SceneError naming
  /// render.mesh_resolution (and the levels on offer) for one not built.
  std::shared_ptr<const Mesh> at(int resolution) const;
  std::vector<int> resolutions() const;  ///< 0 first, then the grids, ascending
  std::size_t vertices(int resolution) const { return at(resolution)->positions.size(); }
};

/// check_geometry against the level `scene` names (render.mesh_resolution),
/// placed as the loaded mesh is (place()): what a parameter store checks
/// before it publishes a scene. Throws SceneError.
void check_geometry(const Scene& scene, const MeshLevels& levels);

/// What a session's parameter store checks: the level exists, and
/// check_geometry_public against the source mesh's bounding box (the box the
/// public proxy describes), so an answer never depends on the vertices.
void check_geometry_public(const Scene& scene, const MeshLevels& levels);

}  // namespace caustic
