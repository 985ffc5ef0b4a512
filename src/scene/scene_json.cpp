// SPDX-License-Identifier: LGPL-2.1-or-later
// JSON <-> Scene with strict validation: every value is checked for type,
// finiteness and range, and the message names the key, so that a REST client
// or a scene author sees exactly what to fix.
#include "caustic/scene.hpp"

#include "caustic/json_text.hpp"
#include "glass_json.hpp"
#include "json_reader.hpp"
#include "lathe_json.hpp"
#include "water_json.hpp"
#include "caustic/receiver_cache.hpp"
#include "caustic/receiver_meshes.hpp"
#include "caustic/screen_follow.hpp"
#include "caustic/spectral.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>
#include <span>
#include <sstream>
#include <vector>

namespace caustic {
namespace {

using detail::join;
using detail::Names;
using detail::Reader;
using nlohmann::json;

// One table per set of names: parsing and writing both read it.
constexpr std::pair<const char*, Material> kMaterials[] = {{"refractive", Material::refractive},
                                                           {"reflective", Material::reflective}};
constexpr std::pair<const char*, Shape> kShapes[] = {
    {"slab", Shape::slab}, {"solid", Shape::solid}, {"surface", Shape::surface}};
constexpr std::pair<const char*, LightType> kLightTypes[] = {{"directional", LightType::directional},
                                                             {"point", LightType::point}};
constexpr std::pair<const char*, PointModel> kPointModels[] = {{"approximate", PointModel::approximate},
                                                               {"exact", PointModel::exact}};
constexpr std::pair<const char*, IntensityMode> kIntensityModes[] = {{"energy", IntensityMode::energy},
                                                                     {"report", IntensityMode::report}};
constexpr std::pair<const char*, Fidelity> kFidelities[] = {{"auto", Fidelity::automatic}, {"manual", Fidelity::manual}};
constexpr std::pair<const char*, ExposureMode> kExposureModes[] = {{"auto", ExposureMode::automatic},
                                                                   {"manual", ExposureMode::manual}};
constexpr std::pair<const char*, ToneMap> kToneMaps[] = {{"global", ToneMap::global}, {"local", ToneMap::local}};
constexpr std::pair<const char*, optics::Illuminant> kSpectra[] = {{"d65", optics::Illuminant::d65},
                                                                   {"e", optics::Illuminant::equal},
                                                                   {"blackbody", optics::Illuminant::blackbody},
                                                                   {"led", optics::Illuminant::led}};


ObjectParams read_object(Reader r) {
  ObjectParams o;
  o.material = r.choice("material", o.material, Names<Material>(kMaterials));
  o.shape = r.choice("shape", o.shape, Names<Shape>(kShapes));
  if (o.shape != Shape::slab && o.material == Material::reflective)
    throw SceneError(r.key("shape"), std::string(o.shape == Shape::solid ? "a solid is glass" : "light enters a surface") +
                                         ": it needs object.material \"refractive\"");
  o.ior = r.number("ior", o.ior, 1.0, 10.0);
  // "none" says "no glass" where a null cannot: in a patch, null restores
  // the scene's own value (a prism's BK7), "none" removes it.
  if (const json* g = r.get("glass"); g && *g != "none") {
    o.glass = glass_from_json(*g, r.key("glass"));
    o.ior = o.glass->index(optics::kLineD);
  }
  o.flat_face_normal = r.vec3("flat_face_normal", o.flat_face_normal, true);
  o.flat_face_offset = r.optional_number("flat_face_offset", -kMaxCoordinate, kMaxCoordinate);
  o.position = r.vec3("position", o.position);
  o.rotation_deg = r.vec3("rotation_deg", o.rotation_deg);
  o.fit_size = r.optional_number("fit_size", 0.0, kMaxCoordinate, true);
  r.reject_unknown();
  return o;
}

LightParams read_light(Reader r) {
  LightParams l;
  l.type = r.choice("type", l.type, Names<LightType>(kLightTypes));
  l.direction = r.vec3("direction", l.direction, true);
  l.position = r.vec3("position", l.position);
  l.point_model = r.choice("point_model", l.point_model, Names<PointModel>(kPointModels));
  l.spectrum.kind = r.choice("spectrum", l.spectrum.kind, Names<optics::Illuminant>(kSpectra));
  l.spectrum.kelvin = r.number("temperature_k", l.spectrum.kelvin, 1000.0, 40000.0);
  r.reject_unknown();
  return l;
}

// The receiver's shape `name` from the scene's table, placed at s.
ShapedMesh read_shape(Reader& r, const ScreenParams& s, const std::shared_ptr<const ReceiverMeshTable>& shapes) {
  const std::string name = r.string("mesh", "", 64);
  if (shapes && shapes->meshes.count(name)) return {name, shape_mesh(shapes, name, s.center, s.normal, s.up)};
  // The names are public (a viewer draws the shapes); what was sent is not repeated.
  std::string names;
  if (shapes)
    for (const auto& [n, file] : shapes->files) names += (names.empty() ? "" : ", ") + n;
  throw SceneError(r.key("mesh"), names.empty() ? "names a shape, and this scene's receiver_meshes lists none"
                                                : "must be one of this scene's receiver_meshes: " + names);
}

ScreenParams read_screen(Reader r, const std::optional<double>& focus_distance, const ObjectParams& object,
                         const LightParams& light, const std::shared_ptr<const ReceiverMeshTable>& shapes) {
  ScreenParams s;
  // A mirror focused by focus_distance: the screen goes where the reflection goes.
  if (const auto n = reflected_screen_normal(object, light); n && focus_distance && !r.has("normal") && !r.has("center")) {
    s.normal = *n;
    if (std::abs(s.normal.y) > 0.999) s.up = {0, 0, 1};  // reflected along y: the default up would be parallel
  }
  s.normal = r.vec3("normal", s.normal, true);
  s.up = r.vec3("up", s.up, true);
  // Gram-Schmidt: the image's vertical axis lies in the screen plane.
  const glm::dvec3 in_plane = s.up - glm::dot(s.up, s.normal) * s.normal;
  if (glm::length(in_plane) < 1e-6) throw SceneError(r.key("up"), "must not be parallel to " + r.key("normal"));
  s.up = glm::normalize(in_plane);
  if (r.has("center")) {
    s.center = r.vec3("center", s.center);
  } else if (focus_distance) {
    r.get("center");
    s.center = object.position - *focus_distance * s.normal;
    // The same bound a written centre has: a far object and a long focus
    // must not produce a scene that validation then refuses.
    for (int i = 0; i < 3; ++i)
      if (std::abs(s.center[i]) > kMaxCoordinate)
        throw SceneError("focus_distance", "places screen.center beyond the coordinate limit of 1e6");
  } else {
    s.center = r.vec3("center", s.center);
  }
  if (r.has("lathe") && r.has("mesh")) throw SceneError(r.key("mesh"), "a receiver is a lathe or a mesh, not both");
  if (r.has("mesh")) {
    for (const char* k : {"width", "height"})
      if (r.has(k)) throw SceneError(r.key(k), "a mesh's size is its own: leave width and height out");
    s.shaped = read_shape(r, s, shapes);
    s.width = s.height = 1;
  } else if (r.has("lathe")) {
    // Its size is its profile: a width or height beside it would be ignored.
    for (const char* k : {"width", "height"})
      if (r.has(k)) throw SceneError(r.key(k), "a lathe's size is its profile: leave width and height out");
    s.lathe = detail::read_lathe(r.child("lathe"));
    s.width = s.height = 1;
    s.lathe->mesh = lathe_mesh(s.lathe->profile, s.lathe->segments, s.center, s.normal, s.up);
  } else {
    // A rectangle; a null lathe or mesh is the default, not an unknown key.
    r.get("lathe"), r.get("mesh");
    s.width = r.number("width", s.width, 0.0, kMaxCoordinate, true);
    s.height = r.number("height", s.height, 0.0, kMaxCoordinate, true);
  }
  s.follow_light = r.boolean("follow_light", s.follow_light);
  r.reject_unknown();
  return s;
}

RenderParams read_render(Reader r) {
  RenderParams p;
  p.width = r.integer("width", p.width, 16, 8192);
  p.height = r.integer("height", p.height, 16, 8192);
  p.intensity = r.choice("intensity", p.intensity, Names<IntensityMode>(kIntensityModes));
  p.fresnel = r.boolean("fresnel", p.fresnel);
  p.report_plane_distance = r.number("report_plane_distance", p.report_plane_distance, 0.0, kMaxCoordinate, true);
  p.fidelity = r.choice("fidelity", p.fidelity, Names<Fidelity>(kFidelities));
  p.accuracy_target = r.number("accuracy_target", p.accuracy_target, 0.0, 1.0, true);
  p.mesh_resolution = r.integer("mesh_resolution", p.mesh_resolution, 0, 2048);
  if (p.mesh_resolution == 1) throw SceneError(r.key("mesh_resolution"), "must be 0 (the mesh as loaded) or at least 2");
  p.wavelengths = r.integer("wavelengths", p.wavelengths, 1, optics::kMaxWavelengths);
  p.still_wavelengths = r.integer("still_wavelengths", p.still_wavelengths, 1, optics::kMaxWavelengths);
  p.light_grid = r.integer("light_grid", p.light_grid, 16, 2048);
  r.reject_unknown();
  return p;
}

PostParams read_post(Reader r) {
  PostParams p;
  p.exposure_mode = r.choice("exposure_mode", p.exposure_mode, Names<ExposureMode>(kExposureModes));
  p.exposure = r.number("exposure", p.exposure, 0.0, 1e4, true);
  p.auto_percentile = r.number("auto_percentile", p.auto_percentile, 0.5, 1.0);
  p.exposure_adapt_s = r.number("exposure_adapt_s", p.exposure_adapt_s, 0.0, 10.0);
  p.tone_map = r.choice("tone_map", p.tone_map, Names<ToneMap>(kToneMaps));
  p.local_strength = r.number("local_strength", p.local_strength, 0.0, 1.0);
  p.gamma = r.number("gamma", p.gamma, 0.1, 10.0);
  p.bloom_threshold = r.number("bloom_threshold", p.bloom_threshold, 0.0, 1e6);
  p.bloom_strength = r.number("bloom_strength", p.bloom_strength, 0.0, 100.0);
  p.bloom_radius = r.number("bloom_radius", p.bloom_radius, 0.0, 64.0);
  r.reject_unknown();
  return p;
}

template <typename Enum>
const char* name_of(Enum value, Names<Enum> options) {
  for (const auto& [name, v] : options)
    if (v == value) return name;
  return "";
}

json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

template <typename T>
json opt(const std::optional<T>& v) { return v ? json(*v) : json(nullptr); }

}  // namespace

Scene scene_from_json(const json& j, const std::filesystem::path& base_dir,
                      std::shared_ptr<const ReceiverMeshTable> loaded) {
  Reader r(j, "");
  Scene s;
  s.base_dir = base_dir;
  s.name = r.text("name", 200);
  s.description = r.text("description", 2000);
  // Water makes its own surface: a mesh it names is ignored (with a warning, scene_warnings.hpp).
  if (r.get("water")) s.water = detail::read_water(r.child("water"));
  if (!r.has("mesh") && !s.water) throw SceneError("mesh", "is required (path of the caustic face OBJ)");
  s.mesh = r.string("mesh", "");
  if (s.mesh.empty() && !s.water) throw SceneError("mesh", "must not be empty");
  // A NUL ended the name where the system reads it ("a.obj\u0000junk" loaded a.obj).
  for (unsigned char ch : s.mesh)
    if (ch < 0x20 || ch == 0x7f) throw SceneError("mesh", "must not hold control characters");
  s.focus_distance = r.optional_number("focus_distance", 0.0, kMaxCoordinate, true);
  s.object = read_object(r.child("object"));
  if (s.water) {
    // A shape written (null is the default, which water makes a surface) must be the surface.
    const json* object = r.get("object");
    if (object && object->is_object() && object->value("shape", json()) != nullptr && s.object.shape != Shape::surface)
      throw SceneError("object.shape", std::string("is \"") + name_of(s.object.shape, Names<Shape>(kShapes)) +
                                           "\", but this is a water scene: its object is the water's surface "
                                           "(\"surface\", or leave object.shape out)");
    s.object.shape = Shape::surface;
    // Fitting centres the mesh's box, which the waves move: the pool would bob.
    if (s.object.fit_size) throw SceneError("object.fit_size", "water's size is water.size: leave fit_size out");
  }
  s.light = read_light(r.child("light"));
  // Read before the receivers that name them; a patch's are the ones already read.
  if (const json* table = r.get("receiver_meshes")) {
    if (loaded && *table != json(loaded->files))
      throw SceneError("receiver_meshes", "is the scene file's: it cannot change here");
    s.receiver_meshes = loaded ? loaded : std::make_shared<const ReceiverMeshTable>(load_receiver_meshes(*table, base_dir));
  }
  // Refused before it is read: reading builds a lathe's or a shape's
  // triangles, work a refusal should not cost.
  if (const json* screen = r.get("screen"); screen && screen->is_object()) {
    if (screen->value("lathe", json()) != nullptr)
      throw SceneError("screen.lathe", "the screen is a rectangle; a lathe is one of the receivers");
    if (screen->value("mesh", json()) != nullptr)
      throw SceneError("screen.mesh", "the screen is a rectangle; a mesh is one of the receivers");
  }
  s.screen = read_screen(r.child("screen"), s.focus_distance, s.object, s.light, s.receiver_meshes);
  if (const json* list = r.get("receivers")) {
    if (!list->is_array() || list->size() > kMaxReceivers)
      throw SceneError("receivers", "must be an array of at most " + std::to_string(kMaxReceivers) + " rectangles");
    for (std::size_t i = 0; i < list->size(); ++i) {
      const std::string where = "receivers[" + std::to_string(i) + "]";
      s.receivers.push_back(read_screen(Reader((*list)[i], where), std::nullopt, s.object, s.light,
                                        s.receiver_meshes));
      if (s.receivers.back().follow_light) throw SceneError(where + ".follow_light", "only the screen follows the light");
    }
  }
  s.render = read_render(r.child("render"));
  // A grid level resamples a face over its flat face; a solid's body came out an open sheet the engine refused.
  if (s.object.shape == Shape::solid && s.render.fidelity == Fidelity::manual && s.render.mesh_resolution != 0)
    throw SceneError("render.mesh_resolution", "must be 0 for a solid, which is traced as loaded (a grid level "
                                               "resamples a slab's face)");
  if (!s.receivers.empty() && s.render.intensity == IntensityMode::report)
    throw SceneError("render.intensity", "\"report\" measures against a plane behind the screen alone; with "
                                         "receivers use \"energy\"");
  s.post = read_post(r.child("post"));
  r.reject_unknown();
  check_frame_cost(s);
  return s;
}

static json screen_to_json(const ScreenParams& screen) {
  json out = {{"center", vec(screen.center)}, {"normal", vec(screen.normal)}, {"up", vec(screen.up)},
              {"follow_light", screen.follow_light}};
  if (screen.shaped) {
    out["mesh"] = screen.shaped->name;
  } else if (screen.lathe) {
    json profile = json::array();
    for (const glm::dvec2& p : screen.lathe->profile) profile.push_back({p.x, p.y});
    out["lathe"] = {{"profile", profile}, {"segments", screen.lathe->segments}};
  } else {
    out["width"] = screen.width;
    out["height"] = screen.height;
  }
  return out;
}

json scene_to_json(const Scene& s) {
  const auto& o = s.object;
  json receivers = json::array();
  for (const auto& r : s.receivers) receivers.push_back(screen_to_json(r));
  const auto& l = s.light;
  return json{
      {"name", s.name},
      {"description", s.description},
      {"mesh", s.mesh},
      {"receiver_meshes", s.receiver_meshes ? json(s.receiver_meshes->files) : json(nullptr)},
      {"focus_distance", opt(s.focus_distance)},
      {"object",
       {{"material", name_of(o.material, Names<Material>(kMaterials))},
        {"shape", name_of(o.shape, Names<Shape>(kShapes))},
        {"ior", o.ior},
        {"glass", o.glass ? glass_to_json(*o.glass) : json(nullptr)},
        {"flat_face_normal", vec(o.flat_face_normal)},
        {"flat_face_offset", opt(o.flat_face_offset)},
        {"position", vec(o.position)},
        {"rotation_deg", vec(o.rotation_deg)},
        {"fit_size", opt(o.fit_size)}}},
      {"light",
       {{"type", name_of(l.type, Names<LightType>(kLightTypes))},
        {"direction", vec(l.direction)},
        {"position", vec(l.position)},
        {"point_model", name_of(l.point_model, Names<PointModel>(kPointModels))},
        {"spectrum", name_of(l.spectrum.kind, Names<optics::Illuminant>(kSpectra))},
        {"temperature_k", l.spectrum.kelvin}}},
      {"screen", screen_to_json(s.screen)},
      {"receivers", receivers},
      {"render",
       {{"width", s.render.width},
        {"height", s.render.height},
        {"intensity", name_of(s.render.intensity, Names<IntensityMode>(kIntensityModes))},
        {"fresnel", s.render.fresnel},
        {"report_plane_distance", s.render.report_plane_distance},
        {"fidelity", name_of(s.render.fidelity, Names<Fidelity>(kFidelities))},
        {"accuracy_target", s.render.accuracy_target},
        {"mesh_resolution", s.render.mesh_resolution},
        {"wavelengths", s.render.wavelengths},
        {"still_wavelengths", s.render.still_wavelengths},
        {"light_grid", s.render.light_grid}}},
      {"water", s.water ? detail::water_to_json(*s.water) : json(nullptr)},
      {"post",
       {{"exposure_mode", name_of(s.post.exposure_mode, Names<ExposureMode>(kExposureModes))},
        {"exposure", s.post.exposure},
        {"auto_percentile", s.post.auto_percentile},
        {"exposure_adapt_s", s.post.exposure_adapt_s},
        {"tone_map", name_of(s.post.tone_map, Names<ToneMap>(kToneMaps))},
        {"local_strength", s.post.local_strength},
        {"gamma", s.post.gamma},
        {"bloom_threshold", s.post.bloom_threshold},
        {"bloom_strength", s.post.bloom_strength},
        {"bloom_radius", s.post.bloom_radius}}},
  };
}

void validate_scene(const Scene& scene) {
  scene_from_json(scene_to_json(scene), scene.base_dir, scene.receiver_meshes);
  // Parsing normalises vectors; a scene built in code must already be normal.
  auto unit = [](const glm::dvec3& v) { return std::abs(glm::length(v) - 1.0) < 1e-9; };
  if (!unit(scene.object.flat_face_normal)) throw SceneError("object.flat_face_normal", "must be a unit vector");
  if (!unit(scene.light.direction)) throw SceneError("light.direction", "must be a unit vector");
  if (!unit(scene.screen.normal)) throw SceneError("screen.normal", "must be a unit vector");
  if (!unit(scene.screen.up) || std::abs(glm::dot(scene.screen.up, scene.screen.normal)) > 1e-9)
    throw SceneError("screen.up", "must be a unit vector perpendicular to screen.normal");
  for (std::size_t i = 0; i < scene.receivers.size(); ++i) {
    const auto& r = scene.receivers[i];
    const std::string where = "receivers[" + std::to_string(i) + "]";
    if (!unit(r.normal)) throw SceneError(where + ".normal", "must be a unit vector");
    if (!unit(r.up) || std::abs(glm::dot(r.up, r.normal)) > 1e-9)
      throw SceneError(where + ".up", "must be a unit vector perpendicular to its normal");
  }
}

Scene load_scene(const std::filesystem::path& file, nlohmann::json* written) {
  const FileText read = read_file_text(file, kMaxSceneFileBytes);
  if (read.not_a_file) throw SceneError("", "scene file " + file.string() + " is a folder, pipe, socket, device or kernel file, not a file");
  if (!read.opened) throw SceneError("", "cannot open scene file " + file.string() + why_unread(read));
  if (read.too_large)
    throw SceneError("", "scene file " + file.string() + " is larger than " +
                             std::to_string(kMaxSceneFileBytes >> 20) + " MiB; a scene names its meshes, never holds them");
  const std::string& text = read.text;
  JsonTextError error;
  auto j = parse_json_text(text, &error);
  if (!j)
    throw SceneError("", "scene file " + file.string() + " is not valid JSON: " + where_json_broke(text, error));
  Scene scene = scene_from_json(*j, file.parent_path());
  if (written) *written = std::move(*j);
  return scene;
}

}  // namespace caustic
