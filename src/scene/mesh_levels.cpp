// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/mesh_levels.hpp"

#include <string>

namespace caustic {

std::shared_ptr<const Mesh> MeshLevels::at(int resolution) const {
  if (resolution == 0) return source;
  if (auto it = resampled.find(resolution); it != resampled.end()) return it->second;
  std::string offered = "0";
  for (const auto& [n, mesh] : resampled) offered += ", " + std::to_string(n);
  throw SceneError("render.mesh_resolution", "must be one of the levels this scene offers: " + offered);
}

void check_geometry(const Scene& scene, const MeshLevels& levels) {
  // Every level placed as the loaded mesh is (as the engine is told to):
  // placed by its own bounds, a coarser level sat elsewhere, and the render
  // refused what the public box had passed.
  check_geometry(scene, *levels.at(scene.render.mesh_resolution), levels.place(scene.object));
}

void check_geometry_public(const Scene& scene, const MeshLevels& levels) {
  levels.at(scene.render.mesh_resolution);
  check_geometry_public(scene, levels.place(scene.object));
}

Placement MeshLevels::place(const ObjectParams& object) const {
  if (bounds && bounds->normal == object.flat_face_normal) return place_object(object, *bounds);
  return place_object(object, *source);
}

std::vector<int> MeshLevels::resolutions() const {
  std::vector<int> out{0};
  for (const auto& [n, mesh] : resampled) out.push_back(n);
  return out;
}

}  // namespace caustic
