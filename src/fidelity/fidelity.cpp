// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/fidelity.hpp"
#include "caustic/fnv1a.hpp"
#include "caustic/json_text.hpp"
#include "caustic/screen_follow.hpp"
#include "caustic/spectral.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

namespace caustic {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "causticd-calibration-1";


std::tuple<std::size_t, int, int, int> cost(const CalibrationEntry& e) {
  return {e.vertices, e.config.light_grid, e.config.point_model == PointModel::exact, e.config.fresnel};
}

template <typename T>
T field(const json& j, const std::string& key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw SceneError(where + key, "is missing");
  const json& v = j.at(key);
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    // The library's get<int>() cuts 2.7 to 2, wraps -5 into a count of
    // 18 quintillion and 1e30 into anything: a whole number in range, or none.
    const auto top = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
    const auto bottom = static_cast<std::int64_t>(std::numeric_limits<T>::min());
    bool fits = false;
    if (v.is_number_unsigned()) {
      fits = v.get<std::uint64_t>() <= top;
    } else if (v.is_number_integer()) {  // either sign: a document built in code keeps 5 signed
      const std::int64_t n = v.get<std::int64_t>();
      fits = n < 0 ? std::is_signed_v<T> && n >= bottom : static_cast<std::uint64_t>(n) <= top;
    }
    if (!fits) throw SceneError(where + key, "must be a whole number from " + std::to_string(std::numeric_limits<T>::min()) +
                                                 " to " + std::to_string(std::numeric_limits<T>::max()));
    return v.get<T>();
  }
  try {
    return v.get<T>();
  } catch (const json::exception&) {
    throw SceneError(where + key, "has the wrong type");
  }
}

}  // namespace

const char* point_model_name(PointModel m) { return m == PointModel::exact ? "exact" : "approximate"; }

std::string scene_fingerprint(const Scene& scene, const Mesh& mesh) {
  json j = scene_to_json(scene);
  for (const char* k : {"name", "description", "mesh", "post", "focus_distance"}) j.erase(k);
  j["light"].erase("point_model");
  for (const char* k : {"width", "height", "fresnel", "fidelity", "accuracy_target", "mesh_resolution", "light_grid"})
    j["render"].erase(k);
  std::uint64_t h = fnv1a(j.dump());
  // The mesh by the bits of every position and corner index: a weighted sum
  // printed to 7 digits once kept its value when two vertices moved by +d
  // and -d (and is about 0 for any designed face), so a stale calibration
  // was taken for the new mesh. Fed byte by byte, low byte first, so that
  // the fingerprint is the same on any host.
  const auto word = [&h](std::uint32_t v) {
    for (int b = 0; b < 4; ++b) h = fnv1a_byte(h, static_cast<unsigned char>(v >> (8 * b)));
  };
  word(static_cast<std::uint32_t>(mesh.positions.size()));
  word(static_cast<std::uint32_t>(mesh.triangles.size()));
  for (const glm::vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k) word(std::bit_cast<std::uint32_t>(p[k]));
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) word(t[k]);
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

json calibration_to_json(const Calibration& c) {
  json entries = json::array();
  for (const auto& e : c.entries)
    entries.push_back({{"mesh_resolution", e.config.mesh_resolution},
                       {"point_model", point_model_name(e.config.point_model)},
                       {"fresnel", e.config.fresnel},
                       {"vertices", e.vertices},
                       {"relative_l1", e.relative_l1},
                       {"relative_rmse", e.relative_rmse},
                       {"ssim", e.ssim},
                       {"ray_ms", e.ray_ms}});
  for (std::size_t i = 0; i < c.entries.size(); ++i) {
    if (c.entries[i].streamed_l1) entries[i]["streamed_l1"] = *c.entries[i].streamed_l1;
    if (c.entries[i].streamed_ssim) entries[i]["streamed_ssim"] = *c.entries[i].streamed_ssim;
    if (c.entries[i].config.light_grid) entries[i]["light_grid"] = c.entries[i].config.light_grid;
  }
  return {{"format", kFormat},       {"fingerprint", c.fingerprint}, {"reference_photons", c.reference_photons},
          {"width", c.width},        {"height", c.height},           {"compare_factor", c.compare_factor},
          {"renderer", c.renderer},  {"streamed_width", c.streamed_width}, {"streamed_height", c.streamed_height},
          {"entries", entries}};
}

Calibration calibration_from_json(const json& j) {
  if (!j.is_object() || j.value("format", "") != kFormat)
    throw SceneError("format", std::string("must be \"") + kFormat + "\"");
  Calibration c;
  c.fingerprint = field<std::string>(j, "fingerprint", "");
  c.reference_photons = field<std::uint64_t>(j, "reference_photons", "");
  c.width = field<int>(j, "width", "");
  c.height = field<int>(j, "height", "");
  c.compare_factor = field<int>(j, "compare_factor", "");
  c.renderer = field<std::string>(j, "renderer", "");
  if (j.contains("streamed_width")) {
    c.streamed_width = field<int>(j, "streamed_width", "");
    c.streamed_height = field<int>(j, "streamed_height", "");
  }
  const json& entries = j.contains("entries") ? j["entries"] : json();
  if (!entries.is_array()) throw SceneError("entries", "must be an array");
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const std::string where = "entries[" + std::to_string(i) + "].";
    CalibrationEntry e;
    e.config.mesh_resolution = field<int>(entries[i], "mesh_resolution", where);
    // render.mesh_resolution's own range: an entry outside it matches no level.
    if (e.config.mesh_resolution < 0 || e.config.mesh_resolution == 1 || e.config.mesh_resolution > 2048)
      throw SceneError(where + "mesh_resolution", "must be 0 (the mesh as loaded) or in [2, 2048]");
    const auto model = field<std::string>(entries[i], "point_model", where);
    if (model != "exact" && model != "approximate")
      throw SceneError(where + "point_model", "must be \"exact\" or \"approximate\"");
    e.config.point_model = model == "exact" ? PointModel::exact : PointModel::approximate;
    e.config.fresnel = field<bool>(entries[i], "fresnel", where);
    if (entries[i].contains("light_grid")) {  // a solid's
      e.config.light_grid = field<int>(entries[i], "light_grid", where);
      if (e.config.light_grid < 16 || e.config.light_grid > 2048)
        throw SceneError(where + "light_grid", "must be in [16, 2048]");
    }
    e.vertices = field<std::size_t>(entries[i], "vertices", where);
    e.relative_l1 = field<double>(entries[i], "relative_l1", where);
    e.relative_rmse = field<double>(entries[i], "relative_rmse", where);
    e.ssim = field<double>(entries[i], "ssim", where);
    e.ray_ms = field<double>(entries[i], "ray_ms", where);
    // An error is a share of the light: 100 (10,000%) is already no picture.
    if (!(e.relative_l1 >= 0 && e.relative_l1 <= 100))
      throw SceneError(where + "relative_l1", "must be a number in [0, 100]");
    for (const auto& [key, value] : {std::pair{"streamed_l1", &e.streamed_l1}, std::pair{"streamed_ssim", &e.streamed_ssim}})
      if (entries[i].contains(key)) {
        *value = field<double>(entries[i], key, where);
        if (!(**value >= -1) || !std::isfinite(**value)) throw SceneError(where + key, "must be a finite number");
      }
    c.entries.push_back(e);
  }
  return c;
}

std::optional<Calibration> load_calibration(const std::filesystem::path& file, const std::string& fingerprint) {
  const FileText read = read_file_text(file, kMaxCalibrationFileBytes);
  // Taken without being named (beside its scene): one that is there but no
  // file is an error, not "no calibration" (a pipe once held render up).
  if (read.not_a_file)
    throw SceneError("", file.filename().string() + " is a folder, pipe, socket, device or kernel file, not a calibration file");
  if (!read.opened) return std::nullopt;
  if (read.too_large)
    throw SceneError("", file.filename().string() + " is larger than " + std::to_string(kMaxCalibrationFileBytes >> 10) +
                             " KiB; a calibration holds a few entries");
  const std::string& text = read.text;
  JsonTextError error;
  const auto parsed = parse_json_text(text, &error);
  if (!parsed)
    throw SceneError("", file.filename().string() + " is not valid JSON: " + where_json_broke(text, error));
  const json& j = *parsed;
  Calibration c;
  try {
    c = calibration_from_json(j);
  } catch (const SceneError& e) {
    throw SceneError("", file.filename().string() + ": " + e.what());
  }
  if (c.fingerprint != fingerprint) return std::nullopt;
  return c;
}

std::string stale_calibration_note(const std::filesystem::path& scene_file, const std::optional<Calibration>& loaded) {
  std::error_code ec;
  const auto file = calibration_path(scene_file);
  if (loaded || !std::filesystem::exists(file, ec)) return "";
  return file.filename().string() + " was made for other physics than these (the scene or its mesh changed, other " +
         "parameters, or an older causticd): fidelity \"auto\" renders the full model; causticd calibrate --scene " +
         scene_file.string() + " makes one for them";
}

bool meets_target(const CalibrationEntry& e, double target) { return worst_error(e) <= target; }

double worst_error(const CalibrationEntry& e) {
  double worst = e.relative_l1;
  if (e.streamed_l1) worst = std::max(worst, *e.streamed_l1);
  if (e.streamed_ssim) worst = std::max(worst, 1 - *e.streamed_ssim);
  return worst;
}

int light_grid_bound(const Scene& scene) {
  return scene.object.shape == Shape::solid ? scene.render.light_grid : 0;
}

FidelityChoice choose_fidelity(const std::optional<Calibration>& calibration, double target, const MeshLevels& levels,
                               int light_grid) {
  FidelityChoice choice;
  if (!calibration) return choice;
  const CalibrationEntry* cheapest = nullptr;
  const CalibrationEntry* best = nullptr;
  for (const auto& e : calibration->entries) {
    if (e.config.mesh_resolution != 0 && !levels.resampled.count(e.config.mesh_resolution)) continue;
    // Auto chooses grids up to the scene's own (docs/accuracy.md); the
    // fingerprint leaves the grid out, so a calibration made when the
    // scene's grid was finer still matches and offers grids above it.
    if (light_grid > 0 && e.config.light_grid > light_grid) continue;
    if (!best || worst_error(e) < worst_error(*best)) best = &e;
    if (meets_target(e, target) && (!cheapest || cost(e) < cost(*cheapest))) cheapest = &e;
  }
  const CalibrationEntry* pick = cheapest ? cheapest : best;
  if (!pick) return choice;
  choice.config = pick->config;
  choice.expected_l1 = pick->relative_l1;
  choice.meets_target = cheapest != nullptr;
  return choice;
}

std::vector<std::pair<std::string, std::string>> fidelity_overrides(const nlohmann::json& written, const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  if (scene.render.fidelity != Fidelity::automatic || !written.is_object()) return out;
  for (const auto& [section, key] : kFidelityAutoKeys) {
    const auto part = written.find(section);
    if (part == written.end() || !part->is_object()) continue;
    const auto value = part->find(key);
    if (value == part->end() || value->is_null()) continue;
    const std::string name = std::string(section) + "." + key;
    if (name == "render.light_grid" && scene.object.shape != Shape::solid) continue;  // moot: shape_overrides says so
    // A solid's own grid (its scene's, --set included) stays the finest
    // "auto" may take; a patch's is chosen over like the other keys.
    if (name == "render.light_grid")
      out.emplace_back(name, name + " is chosen by render.fidelity \"auto\", no finer than the scene's own grid, so "
                                    "the value written may not be the one used; set render.fidelity to \"manual\" "
                                    "to use it as written");
    else
      out.emplace_back(name, name + " is chosen by render.fidelity \"auto\", which overrides the value written; set "
                                    "render.fidelity to \"manual\" to use it");
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> scene_overrides(const nlohmann::json& written, const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  for (auto&& part : {fidelity_overrides(written, scene), follow_overrides(written, scene),
                      spectral_overrides(written, scene), shape_overrides(written, scene),
                      setting_overrides(written, scene)})
    out.insert(out.end(), part.begin(), part.end());
  return out;
}

Scene resolve_fidelity(Scene scene, const FidelityChoice& choice) {
  if (scene.render.fidelity != Fidelity::automatic) return scene;
  scene.render.mesh_resolution = choice.config.mesh_resolution;
  scene.light.point_model = choice.config.point_model;
  scene.render.fresnel = choice.config.fresnel;
  if (choice.config.light_grid > 0 && scene.object.shape == Shape::solid)
    scene.render.light_grid = choice.config.light_grid;
  return scene;
}

json describe_fidelity(const Scene& scene, const Mesh& source, const MeshLevels& levels,
                       const std::optional<Calibration>& calibration) {
  const bool automatic = scene.render.fidelity == Fidelity::automatic;
  json j{{"mode", automatic ? "auto" : "manual"},
         {"accuracy_target", scene.render.accuracy_target},
         {"mesh_resolution", scene.render.mesh_resolution},
         // A grid level's count is its resolution squared; the loaded mesh's
         // is not told (this goes to every session: the mesh stays hidden).
         {"vertices", scene.render.mesh_resolution ? json(levels.vertices(scene.render.mesh_resolution)) : json()},
         {"point_model", point_model_name(scene.light.point_model)},
         {"fresnel", scene.render.fresnel},
         {"light_grid", scene.object.shape == Shape::solid ? json(scene.render.light_grid) : json()},
         {"levels", levels.resolutions()},
         {"calibrated", calibration.has_value()},
         {"expected_relative_l1", nullptr},
         {"expected_streamed_l1", nullptr},
         {"expected_streamed_ssim", nullptr},
         {"meets_target", nullptr}};
  if (!calibration) return j;
  const FidelityConfig now{scene.render.mesh_resolution, scene.light.point_model, scene.render.fresnel,
                          scene.object.shape == Shape::solid ? scene.render.light_grid : 0};
  for (const auto& e : calibration->entries)
    if (e.config == now) {
      j["expected_relative_l1"] = e.relative_l1;
      j["expected_streamed_l1"] = e.streamed_l1 ? json(*e.streamed_l1) : json();
      j["expected_streamed_ssim"] = e.streamed_ssim ? json(*e.streamed_ssim) : json();
      j["meets_target"] = meets_target(e, scene.render.accuracy_target);
    }
  // Moving the light or the object takes the scene away from what was calibrated.
  j["calibration_matches_parameters"] = scene_fingerprint(scene, source) == calibration->fingerprint;
  return j;
}

std::filesystem::path calibration_path(const std::filesystem::path& scene_file) {
  std::filesystem::path p = scene_file;
  return p.replace_extension(".calibration.json");
}

}  // namespace caustic
