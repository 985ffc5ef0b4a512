// SPDX-License-Identifier: LGPL-2.1-or-later
#include "commands.hpp"

#include "caustic/pool.hpp"
#include "caustic/resample.hpp"
#include "caustic/screen_follow.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <set>

#include <fcntl.h>
#include <unistd.h>

namespace caustic::app {

namespace {

// What the scene file and the assignments write that is not what renders:
// a key another setting overrides or leaves unused, and a key assigned
// twice (a --set, then --width). Said once each, never silently dropped.
void warn_overrides(const char* command, const nlohmann::json& file_doc, const std::vector<std::string>& assignments,
                    const Scene& scene) {
  std::vector<nlohmann::json> written{file_doc};
  for (const auto& a : assignments) written.push_back(patch_from_assignment(a));
  std::set<std::string> said;
  for (const auto& w : written)
    for (const auto& [key, detail] : scene_overrides(w, scene))
      if (said.insert(key).second) std::cerr << "causticd " << command << ": warning: " << detail << "\n";
  for (std::size_t i = 0; i < assignments.size(); ++i)
    for (std::size_t j = i + 1; j < assignments.size(); ++j) {
      const std::string key = assignments[i].substr(0, assignments[i].find('='));
      if (key == assignments[j].substr(0, assignments[j].find('=')) && assignments[i] != assignments[j])
        std::cerr << "causticd " << command << ": warning: " << key << ": " << assignments[i] << " is overridden by "
                  << assignments[j] << " (the later one is used)\n";
    }
}

}  // namespace

bool load_scene_and_mesh(const char* command, const std::filesystem::path& file,
                         const std::vector<std::string>& assignments, Scene* scene, Mesh* mesh) {
  try {
    nlohmann::json written;
    *scene = load_scene(file, &written);
    for (const auto& a : assignments) *scene = apply_merge_patch(*scene, patch_from_assignment(a));
    *mesh = water::load_scene_mesh(*scene);
    warn_overrides(command, written, assignments, *scene);
    return true;
  } catch (const SceneError& e) {
    std::cerr << "causticd " << command << ": " << file.string() << ": " << e.what() << "\n";
    return false;
  }
}

bool output_writable(const char* command, const std::filesystem::path& out, const char* flag) {
  const auto dir = std::filesystem::absolute(out).parent_path();
  const auto refuse = [&](const std::string& why) {
    std::cerr << "causticd " << command << ": " << flag << " " << out.string() << ": " << why << "\n";
    return false;
  };
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return refuse("folder " + dir.string() + " does not exist");
  if (std::filesystem::is_directory(out, ec)) return refuse("is a folder");
  // Tried before the work rather than found after it: a file there is
  // opened for writing (and left as it was), a new one made and removed.
  const bool existed = std::filesystem::exists(out, ec);
  const int fd = ::open(out.c_str(), O_WRONLY | (existed ? 0 : O_CREAT | O_EXCL) | O_CLOEXEC | O_NONBLOCK, 0644);
  if (fd < 0) return refuse(std::string("cannot be written (") + std::strerror(errno) + ")");
  ::close(fd);
  if (!existed) std::filesystem::remove(out, ec);
  return true;
}

int run_reporting(const char* command, const std::filesystem::path& scene, const std::function<void()>& body,
                  const char* prefix) {
  try {
    body();
    return ok;
  } catch (const SceneError& e) {
    std::cerr << prefix << "causticd " << command << ": " << scene.string() << ": " << e.what() << "\n";
    return bad_input;
  } catch (const std::exception& e) {
    std::cerr << prefix << "causticd " << command << ": " << e.what() << "\n";
    return runtime_failure;
  }
}

bool load_scene_levels(const char* command, const std::filesystem::path& file,
                       const std::vector<std::string>& assignments, Scene* scene, SceneLevels* out) {
  Mesh mesh;
  if (!load_scene_and_mesh(command, file, assignments, scene, &mesh)) return false;
  try {
    auto source = std::make_shared<const Mesh>(std::move(mesh));
    std::vector<int> resolutions = coarser_resolutions(*source, *scene);
    const int named = scene->render.mesh_resolution;
    if (named != 0 && std::find(resolutions.begin(), resolutions.end(), named) == resolutions.end())
      resolutions.push_back(named);
    out->levels = build_mesh_levels(source, scene->object.flat_face_normal, resolutions);
    // Calibrated as rendered: with the screen where following puts it.
    const Placement placed = out->levels.place(scene->object);
    *scene = follow_light(*scene, placed);
    out->calibration = load_calibration(calibration_path(file), scene_fingerprint(*scene, *source));
    *scene = resolve_fidelity(*scene, choose_fidelity(out->calibration, scene->render.accuracy_target, out->levels));
    return true;
  } catch (const SceneError& e) {
    std::cerr << "causticd " << command << ": " << file.string() << ": " << e.what() << "\n";
    return false;
  }
}

std::string describe_choice(const Scene& scene, const SceneLevels& levels) {
  const auto d = describe_fidelity(scene, *levels.levels.source, levels.levels, levels.calibration);
  char line[300];
  const int n = scene.render.mesh_resolution;
  std::snprintf(line, sizeof line, "fidelity: %s; mesh %s (%zu vertices), point model %s, Fresnel %s; %s",
                d["mode"].get<std::string>().c_str(), n ? (std::to_string(n) + "^2").c_str() : "as loaded",
                levels.levels.vertices(n), d["point_model"].get<std::string>().c_str(),
                scene.render.fresnel ? "on" : "off",
                d["expected_relative_l1"].is_number()
                    ? ("expected relative L1 " + std::to_string(100 * d["expected_relative_l1"].get<double>()).substr(0, 5) +
                       "% (target " + std::to_string(100 * scene.render.accuracy_target).substr(0, 4) + "%)")
                          .c_str()
                    : "not calibrated");
  return line;
}

}  // namespace caustic::app
