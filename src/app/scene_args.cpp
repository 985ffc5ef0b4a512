// SPDX-License-Identifier: LGPL-2.1-or-later
#include "commands.hpp"

#include "caustic/pool.hpp"
#include "caustic/receiver_meshes.hpp"
#include "caustic/resample.hpp"
#include "caustic/scene_warnings.hpp"
#include "caustic/screen_follow.hpp"
#include "caustic/vertex_rays.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <set>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <tuple>

#include <sys/resource.h>

namespace caustic::app {

namespace {

// Every key path a patch writes a value to (objects opened, anything else a
// value), with the value.
std::map<std::string, nlohmann::json> leaf_keys(const nlohmann::json& patch, const std::string& prefix = "") {
  std::map<std::string, nlohmann::json> out;
  if (!patch.is_object() || patch.empty()) {
    out.emplace(prefix, patch);
    return out;
  }
  for (const auto& [key, value] : patch.items()) out.merge(leaf_keys(value, prefix.empty() ? key : prefix + "." + key));
  return out;
}

// What the scene file and the assignments write that is not what renders:
// a key another setting overrides or leaves unused, and a key assigned
// twice (a --set, then --width). Said once each, never silently dropped,
// and as the user wrote it: a flag, not the assignment made of it.
void warn_overrides(const char* command, const nlohmann::json& file_doc, const std::vector<std::string>& assignments,
                    const std::vector<std::string>& flags, const Scene& scene) {
  const auto flag = [&](std::size_t i) { return i < flags.size() ? flags[i] : std::string(); };
  const auto written_as = [&](std::size_t i) { return flag(i).empty() ? assignments[i] : flag(i); };
  std::vector<nlohmann::json> written{file_doc};
  for (const auto& a : assignments) written.push_back(patch_from_assignment(a));
  // And all of them merged as the scene was: a key in the file that a --set
  // overrides (focus_distance, then screen.center) is in no one document.
  nlohmann::json merged = file_doc;
  for (std::size_t i = 1; i < written.size(); ++i) merged.merge_patch(written[i]);
  std::set<std::string> said;
  const auto say = [&](const nlohmann::json& w) {
    for (const auto& [key, detail] : scene_overrides(w, scene))
      if (said.insert(key).second) std::cerr << "causticd " << command << ": warning: " << detail << "\n";
  };
  for (const auto& w : written) say(w);
  say(merged);
  // Two assignments that write one key, directly or inside an object one of
  // them sets whole (post={"gamma":3}, then post.gamma=2), or that reset the
  // object the earlier one wrote into (post.gamma=2, then post=null).
  const auto overrides = [](const std::string& key, const nlohmann::json& value, const std::string& later_key,
                            const nlohmann::json& later) {
    if (later_key == key) return later != value;
    return key.rfind(later_key + ".", 0) == 0 && !later.is_object();
  };
  std::vector<std::map<std::string, nlohmann::json>> leaves;
  for (std::size_t i = 0; i < assignments.size(); ++i) leaves.push_back(leaf_keys(written[i + 1]));
  for (std::size_t i = 0; i < assignments.size(); ++i)
    for (std::size_t j = i + 1; j < assignments.size(); ++j) {
      const auto say_first = [&] {
        for (const auto& [key, value] : leaves[i])
          for (const auto& [later_key, later] : leaves[j])
            if (overrides(key, value, later_key, later)) {
              // A flag is applied after every --set, wherever it was written.
              std::cerr << "causticd " << command << ": warning: " << key << ": " << written_as(i)
                        << " is overridden by " << written_as(j)
                        << (flag(j).empty() ? " (the later one is used)" : " (a flag applies after every --set)")
                        << "\n";
              return;
            }
      };
      say_first();
    }
}

}  // namespace

bool load_scene_and_mesh(const char* command, const std::filesystem::path& file,
                         const std::vector<std::string>& assignments, Scene* scene, Mesh* mesh,
                         const std::vector<std::string>& flags) {
  try {
    nlohmann::json written;
    *scene = load_scene(file, &written);
    std::vector<nlohmann::json> patches;
    for (const auto& a : assignments) patches.push_back(patch_from_assignment(a));
    *scene = apply_merge_patches(*scene, patches);
    *mesh = water::load_scene_mesh(*scene);
    // With the screen where following the light puts it, as every command
    // renders or traces it: a written centre that it moves is then said.
    *scene = follow_light(*scene, place_object(scene->object, *mesh));
    warn_overrides(command, written, assignments, flags, *scene);
    return true;
  } catch (const SceneError& e) {
    std::cerr << "causticd " << command << ": " << file.string() << ": " << e.what() << "\n";
    return false;
  }
}

std::vector<std::filesystem::path> scene_inputs(const std::filesystem::path& file, const Scene& scene) {
  std::vector<std::filesystem::path> inputs{file};
  if (!scene.mesh.empty()) inputs.push_back(scene.mesh_path());
  if (scene.receiver_meshes)
    for (const auto& [name, path] : scene.receiver_meshes->files) inputs.push_back(scene.base_dir / path);
  return inputs;
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
    std::cerr << prefix << "causticd " << command << ": " << failure_text(e) << "\n";
    return runtime_failure;
  }
}

std::string failure_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) return std::string("not enough memory (") + e.what() + ")";
  return e.what();
}

namespace {

// A number from a /proc or cgroup file: the value after `key` (the whole
// file's first word where key is empty), times `unit`; nullopt for "max"
// or anything unreadable.
std::optional<std::uint64_t> read_number(const std::filesystem::path& file, const std::string& key = "",
                                         std::uint64_t unit = 1) {
  std::ifstream in(file);
  for (std::string word; in >> word;) {
    if (!key.empty() && word != key) continue;
    std::string value;
    if (!key.empty() && !(in >> value)) return std::nullopt;
    if (key.empty()) value = word;
    char* end = nullptr;
    errno = 0;
    const unsigned long long n = std::strtoull(value.c_str(), &end, 10);
    if (errno || end == value.c_str() || *end) return std::nullopt;
    return static_cast<std::uint64_t>(n) * unit;
  }
  return std::nullopt;
}

}  // namespace

std::optional<MemoryRoom> memory_room() {
  std::optional<MemoryRoom> room;
  const auto offer = [&](std::uint64_t bytes, const std::string& bound) {
    if (!room || bytes < room->bytes) room = MemoryRoom{bytes, bound};
  };
  if (const auto available = read_number("/proc/meminfo", "MemAvailable:", 1024))
    offer(*available, "the machine's available memory, MemAvailable");
  for (const auto& [resource, key, name] : {std::tuple{RLIMIT_DATA, "VmData:", "its data limit, RLIMIT_DATA"},
                                           std::tuple{RLIMIT_AS, "VmSize:", "its address space limit, RLIMIT_AS"}}) {
    rlimit limit{};
    if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) continue;
    const std::uint64_t used = read_number("/proc/self/status", key, 1024).value_or(0);
    offer(limit.rlim_cur > used ? limit.rlim_cur - used : 0, name);
  }
  // Each level of its cgroup up to the root, v2 ("0::/path": memory.max)
  // or v1 ("N:memory:/path": memory.limit_in_bytes): the limit less what
  // the level holds, page cache it can reclaim (inactive_file) not counted.
  struct Files {
    const char *root, *limit, *usage, *reclaimable;
  };
  static const Files v2{"/sys/fs/cgroup", "memory.max", "memory.current", "inactive_file"},
      v1{"/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file"};
  std::ifstream cgroups("/proc/self/cgroup");
  for (std::string line; std::getline(cgroups, line);) {
    const auto first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = "," + line.substr(first + 1, second - first - 1) + ",";
    const Files* files = line.rfind("0::", 0) == 0                           ? &v2
                         : controllers.find(",memory,") != std::string::npos ? &v1
                                                                              : nullptr;
    if (!files) continue;
    const std::filesystem::path root = files->root;
    std::string path = line.substr(second + 1);
    path.erase(0, path.find_first_not_of('/'));  // under the root, not in place of it
    for (auto dir = (root / path).lexically_normal();; dir = dir.parent_path()) {
      const auto limit = read_number(dir / files->limit), usage = read_number(dir / files->usage);
      // "max" (v2) or a page short of 2^63 (v1): no limit.
      if (limit && usage && *limit < (std::uint64_t{1} << 62)) {
        const auto held = *usage - std::min(*usage, read_number(dir / "memory.stat", files->reclaimable).value_or(0));
        offer(*limit > held ? *limit - held : 0, std::string("its cgroup's ") + files->limit + ", " + dir.string());
      }
      if (dir.string().size() <= root.string().size()) break;
    }
  }
  return room;
}

// A frame's memory, measured as the peak RSS of `render` to EXR and PNG at
// 1024 to 8192 px a side under llvmpipe, where the GL's textures are the
// process's own: about 25 bytes a pixel grey (29 with the local tone map),
// 89 in colour, beside some 70 MB that the GL context adds to what the
// process holds when it checks; rounded up. A hardware GL keeps its
// textures on the card and needs less.
std::uint64_t frame_bytes(int w, int h, bool colour) {
  const auto pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  return 100'000'000 + pixels * (colour ? 96 : 32);
}

// The tracer's memory: an image of doubles per thread, then the sums, the
// image and its EXR; measured as the peak RSS at 4096 and 6000 px a side
// with 1 and 2 threads, 8 bytes a pixel a channel a thread, beside about 9
// grey and 21 in colour; rounded up, with each thread's stack.
std::uint64_t reference_bytes(int w, int h, bool colour, bool tinted, int threads) {
  const auto pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  const auto n = static_cast<std::uint64_t>(threads);
  return 50'000'000 + n * 8'000'000 + pixels * (8 * (tinted ? 3 : 1) * n + (colour ? 24 : 12));
}

int reference_threads(int asked) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return asked > 0 ? std::min(asked, cores) : cores;
}

bool memory_suffices(const char* command, const std::string& named, const std::string& what, std::uint64_t needed,
                     const char* advice) {
  const auto room = memory_room();
  if (!room || needed <= room->bytes) return true;
  char line[200];
  std::snprintf(line, sizeof line, "needs about %.1f GB of memory, and this process can have about %.1f GB",
                needed / 1e9, room->bytes / 1e9);
  std::cerr << "causticd " << command << ": " << named << ": " << what << " " << line << " (" << room->bound
            << "): " << advice << "\n";
  return false;
}

namespace {

// Where the light meets the caustic face from behind, ridges of the face
// shade it, which the per-vertex method sees only in part: the picture
// then holds more light than enters. Said to the operator, whose mesh it
// is; the server never says it (it would describe the secret face).
void warn_self_shading(const char* command, const Scene& scene, const Placement& placed, const Mesh& mesh) {
  const double share = self_shaded_share(scene, placed, mesh);
  if (!(share > 0)) return;
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.3g%%", 100 * share);
  std::cerr << "causticd " << command << ": warning: "
            << (scene.light.type == LightType::point ? "light.position" : "light.direction") << ": the light meets "
            << percent << " of the caustic face's vertices from behind: they carry no light, and the ridges in front "
            << "of them shade more of the face than the per-vertex method sees, so the picture holds more light than "
               "enters (docs/physics.md, section 6); light the object closer to its flat face's normal, or trace it "
               "as a solid (object.shape)\n";
}

}  // namespace

bool load_scene_levels(const char* command, const std::filesystem::path& file,
                       const std::vector<std::string>& assignments, Scene* scene, SceneLevels* out,
                       const std::vector<std::string>& flags) {
  Mesh mesh;
  if (!load_scene_and_mesh(command, file, assignments, scene, &mesh, flags)) return false;
  try {
    auto source = std::make_shared<const Mesh>(std::move(mesh));
    std::vector<int> resolutions = coarser_resolutions(*source, *scene);
    const int named = scene->render.mesh_resolution;
    // A solid has no grid levels (a named one is auto's to override, with a warning).
    if (named != 0 && scene->object.shape != Shape::solid &&
        std::find(resolutions.begin(), resolutions.end(), named) == resolutions.end())
      resolutions.push_back(named);
    out->levels = build_mesh_levels(source, scene->object.flat_face_normal, resolutions);
    // Calibrated as rendered: with the screen where following put it (above).
    const Placement placed = out->levels.place(scene->object);
    warn_self_shading(command, *scene, placed, *source);
    // What the server says of a session's scene, said of the file too: a
    // black picture without a word looks like a broken renderer.
    for (const auto& w : light_warnings(*scene, placed))
      std::cerr << "causticd " << command << ": warning: " << w.key << ": " << w.detail << "\n";
    out->written_light_grid = scene->render.light_grid;
    out->calibration = load_calibration(calibration_path(file), scene_fingerprint(*scene, *source));
    // Not said by calibrate, which is making the new one; "the same --set"
    // only where the user wrote one (--width is no --set, and calibrate has none).
    const auto by_flag = std::count_if(flags.begin(), flags.end(), [](const std::string& f) { return !f.empty(); });
    const bool set = static_cast<std::size_t>(by_flag) < assignments.size();
    if (const auto note = stale_calibration_note(file, out->calibration);
        !note.empty() && std::string_view(command) != "calibrate")
      std::cerr << "causticd " << command << ": warning: " << note << (set ? " (with the same --set)" : "") << "\n";
    *scene = resolve_fidelity(*scene, choose_fidelity(out->calibration, scene->render.accuracy_target, out->levels,
                                                         light_grid_bound(*scene)));
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
  const std::string grid =
      scene.object.shape == Shape::solid ? ", light grid " + std::to_string(scene.render.light_grid) + "^2" : "";
  std::snprintf(line, sizeof line, "fidelity: %s; mesh %s (%zu vertices), point model %s, Fresnel %s%s; %s",
                d["mode"].get<std::string>().c_str(), n ? (std::to_string(n) + "^2").c_str() : "as loaded",
                levels.levels.vertices(n), d["point_model"].get<std::string>().c_str(),
                scene.render.fresnel ? "on" : "off", grid.c_str(),
                d["expected_relative_l1"].is_number()
                    ? ("expected relative L1 " + std::to_string(100 * d["expected_relative_l1"].get<double>()).substr(0, 5) +
                       "% (target " + std::to_string(100 * scene.render.accuracy_target).substr(0, 4) + "%)")
                          .c_str()
                    : "not calibrated");
  return line;
}

}  // namespace caustic::app
