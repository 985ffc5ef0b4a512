#include "commands.hpp"

#include <nlohmann/json.hpp>

#include <iostream>

namespace caustic::app {

bool load_scene_and_mesh(const char* command, const std::filesystem::path& file,
                         const std::vector<std::string>& assignments, Scene* scene, Mesh* mesh) {
  try {
    *scene = load_scene(file);
    for (const auto& a : assignments) *scene = apply_merge_patch(*scene, patch_from_assignment(a));
    *mesh = load_obj(scene->mesh_path());
    return true;
  } catch (const SceneError& e) {
    std::cerr << "causticd " << command << ": " << file.string() << ": " << e.what() << "\n";
    return false;
  }
}

}  // namespace caustic::app
