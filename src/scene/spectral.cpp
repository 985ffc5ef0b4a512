// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/spectral.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace caustic {
namespace {

// The value `written` sets for group.key; null when it sets none (or null).
const nlohmann::json* written_value(const nlohmann::json& written, const char* group, const char* key) {
  if (!written.is_object()) return nullptr;
  const auto g = written.find(group);
  if (g == written.end() || !g->is_object()) return nullptr;
  const auto v = g->find(key);
  return v == g->end() || v->is_null() ? nullptr : &*v;
}

bool writes(const nlohmann::json& written, const char* group, const char* key) {
  return written_value(written, group, key) != nullptr;
}

// The number `written` sets for group.key, if it sets one.
std::optional<double> written_number(const nlohmann::json& written, const char* group, const char* key) {
  const nlohmann::json* v = written_value(written, group, key);
  if (!v || !v->is_number()) return std::nullopt;
  return v->get<double>();
}

}  // namespace

bool spectral(const Scene& scene) { return scene.object.glass && scene.object.material == Material::refractive; }

int frame_wavelengths(const Scene& scene, bool preview, bool still) {
  if (!spectral(scene)) return 0;
  const RenderParams& r = scene.render;
  if (preview) return std::min(r.wavelengths, kPreviewWavelengths);
  return still ? std::max(r.wavelengths, r.still_wavelengths) : r.wavelengths;
}

// What a frame may ask of the renderer, in rays traced (a ray per
// wavelength): a solid's light grid, or a grid level of the face, times the
// wavelengths of its still frame. 2048² rays at 32 wavelengths would take a
// software renderer about 90 s a frame (docs/performance.md's multipass
// figures), hold the session's render thread and, past stall_timeout_s,
// the whole server's watchdog. A curved receiver (a lathe, a shape) costs
// each ray a search of its triangles, about 1.6 rays' work (7 lathes took
// a 512² frame at 32 wavelengths from 5 to 65 s): it counts as 2. Counted
// from what is public (the grid sizes, the receivers), never from the
// loaded mesh (an operator's choice, and a secret).
void check_frame_cost(const Scene& s) {
  const std::uint64_t k = static_cast<std::uint64_t>(std::max(1, frame_wavelengths(s, false, true)));
  const bool solid = s.object.shape == Shape::solid;
  const bool grid_level = s.render.fidelity == Fidelity::manual && s.render.mesh_resolution > 0;
  if (!solid && !grid_level) return;
  std::uint64_t curved = 0;
  for (const ScreenParams& r : s.receivers) curved += r.lathe || r.shaped ? 1 : 0;
  const std::uint64_t side = static_cast<std::uint64_t>(solid ? s.render.light_grid : s.render.mesh_resolution);
  if (side * side * k * (1 + 2 * curved) <= kMaxFrameRays) return;
  throw SceneError(solid ? "render.light_grid" : "render.mesh_resolution",
                   std::to_string(side) + "² rays at " + std::to_string(k) +
                       (k == 1 ? " wavelength" : " wavelengths (the still frame's)") +
                       (curved ? ", each landing on " + std::to_string(curved) + " curved receiver" +
                                     (curved == 1 ? "" : "s") + " (2 rays' work each),"
                               : "") +
                       " are more than a frame may trace (" + std::to_string(kMaxFrameRays) +
                       "); lower it, or render.wavelengths and still_wavelengths");
}

std::vector<SpectralPass> spectral_passes(const Scene& scene, int count) {
  if (!spectral(scene)) return {};
  std::vector<SpectralPass> passes;
  for (const auto& sample : optics::wavelength_samples(scene.light.spectrum, count))
    passes.push_back({sample.nm, scene.object.glass->index(sample.nm), sample.weight});
  return passes;
}

std::vector<std::pair<std::string, std::string>> spectral_overrides(const nlohmann::json& written, const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  // A value equal to the one used is no conflict: a complete scene file (as
  // the designer and scene_to_json write them) carries the derived index
  // and the default temperature.
  const auto ior = written_number(written, "object", "ior");
  if (scene.object.glass && ior && std::abs(*ior - scene.object.ior) > 1e-9)
    out.emplace_back("object.ior", "object.ior is the glass's index at the d line (587.6 nm) while object.glass is "
                                   "set, which overrides the value written; remove object.glass to use one index");
  if (scene.object.glass && scene.object.material == Material::reflective &&
      (writes(written, "object", "glass") || writes(written, "object", "material")))
    out.emplace_back("object.glass", "object.glass has no effect on a mirror (object.material \"reflective\"): "
                                     "reflection sends every wavelength the same way");
  // Without a glass the frame is grey: what shapes a spectral one is moot.
  const auto wavelengths = written_number(written, "render", "wavelengths");
  if (!spectral(scene) && wavelengths && *wavelengths != RenderParams{}.wavelengths)
    out.emplace_back("render.wavelengths", "render.wavelengths counts the wavelengths of a spectral frame; without "
                                           "object.glass the frame is traced once, in grey");
  const auto still = written_number(written, "render", "still_wavelengths");
  if (!spectral(scene) && still && *still != RenderParams{}.still_wavelengths)
    out.emplace_back("render.still_wavelengths", "render.still_wavelengths counts the wavelengths of a spectral "
                                                 "picture left standing; without object.glass the frame is grey");
  if (spectral(scene) && still && scene.render.still_wavelengths < scene.render.wavelengths)
    out.emplace_back("render.still_wavelengths",
                     "render.still_wavelengths (" + std::to_string(scene.render.still_wavelengths) +
                         ") is below render.wavelengths (" + std::to_string(scene.render.wavelengths) +
                         "), which a picture left standing keeps");
  if (!spectral(scene) && writes(written, "light", "spectrum") && scene.light.spectrum.kind != optics::Illuminant::d65)
    out.emplace_back("light.spectrum", "light.spectrum shapes the colours a glass fans out; without object.glass "
                                       "the frame is grey and white-balanced to any light");
  const auto kelvin = written_number(written, "light", "temperature_k");
  if (scene.light.spectrum.kind != optics::Illuminant::blackbody && kelvin && *kelvin != optics::LightSpectrum{}.kelvin)
    out.emplace_back("light.temperature_k",
                     "light.temperature_k is used only by light.spectrum \"blackbody\"; it is ignored for this light");
  return out;
}

std::vector<std::pair<std::string, std::string>> shape_overrides(const nlohmann::json& written, const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  const bool solid = scene.object.shape == Shape::solid;
  if (scene.object.shape != Shape::slab && writes(written, "object", "flat_face_offset"))
    out.emplace_back("object.flat_face_offset", "object.flat_face_offset places the flat face of a slab; a solid "
                                                "or a surface (object.shape) has none, so the value is ignored");
  if (scene.water && written.is_object() && written.contains("mesh") && !written["mesh"].is_null())
    out.emplace_back("mesh", "mesh names a face to load; with a water section the solver makes the surface, so the "
                             "file is not read");
  // A mirror refracts nothing: no index, and no flat face for a point
  // light's entry (its light is aimed at each vertex). Its glass is said
  // by spectral_overrides; a point model "auto" chooses, by fidelity_overrides.
  const bool mirror = scene.object.material == Material::reflective;
  const auto ior = written_number(written, "object", "ior");
  if (mirror && !scene.object.glass && ior && *ior != ObjectParams{}.ior)
    out.emplace_back("object.ior", "object.ior has no effect on a mirror (object.material \"reflective\"): it "
                                   "reflects the light it meets and refracts none");
  if (mirror && scene.light.type == LightType::point && scene.render.fidelity == Fidelity::manual &&
      writes(written, "light", "point_model") && scene.light.point_model != LightParams{}.point_model)
    out.emplace_back("light.point_model", "light.point_model is how a point light enters a slab's flat face; a "
                                          "mirror (object.material \"reflective\") meets it at each vertex, and "
                                          "it is ignored");
  const auto grid = written_number(written, "render", "light_grid");
  if (!solid && grid && *grid != RenderParams{}.light_grid)
    out.emplace_back("render.light_grid", std::string("render.light_grid sizes the light's grid for a solid "
                                                      "(object.shape \"solid\"); a ") +
                                              (scene.object.shape == Shape::surface ? "surface" : "slab") +
                                              " traces one ray per vertex of its face instead");
  return out;
}

std::vector<std::pair<std::string, std::string>> setting_overrides(const nlohmann::json& written, const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  // A key another setting of its own section leaves unused; only a value
  // other than the default is said (a complete scene file writes them all).
  const auto unused = [&](const char* group, const char* key, double fallback, bool used, const char* why) {
    const auto value = written_number(written, group, key);
    if (!used && value && *value != fallback) out.emplace_back(std::string(group) + "." + key, why);
  };
  const RenderParams render;
  const PostParams post;
  unused("render", "report_plane_distance", render.report_plane_distance,
         scene.render.intensity == IntensityMode::report,
         "render.report_plane_distance is used only by render.intensity \"report\"; it is ignored for \"energy\"");
  unused("render", "accuracy_target", render.accuracy_target, scene.render.fidelity == Fidelity::automatic,
         "render.accuracy_target is what render.fidelity \"auto\" aims at; with \"manual\" it is ignored");
  unused("post", "local_strength", post.local_strength, scene.post.tone_map == ToneMap::local,
         "post.local_strength is used only by post.tone_map \"local\"; it is ignored for \"global\"");
  const bool metered = scene.post.exposure_mode == ExposureMode::automatic;
  unused("post", "auto_percentile", post.auto_percentile, metered,
         "post.auto_percentile meters post.exposure_mode \"auto\"; with \"manual\" it is ignored");
  unused("post", "exposure_adapt_s", post.exposure_adapt_s, metered,
         "post.exposure_adapt_s eases post.exposure_mode \"auto\"; with \"manual\" it is ignored");
  unused("post", "bloom_radius", post.bloom_radius, scene.post.bloom_strength > 0,
         "post.bloom_radius spreads the bloom; with post.bloom_strength 0 there is none, and it is ignored");
  unused("post", "bloom_threshold", post.bloom_threshold, scene.post.bloom_strength > 0,
         "post.bloom_threshold starts the bloom; with post.bloom_strength 0 there is none, and it is ignored");
  // A directional light has no position and no point model, a point light
  // no direction: said when written with a value other than the default.
  const LightParams light;
  const bool point = scene.light.type == LightType::point;
  if (!point && writes(written, "light", "position") && scene.light.position != light.position)
    out.emplace_back("light.position", "light.position places a point light; a directional light (light.type) "
                                       "has none, and it is ignored");
  if (!point && writes(written, "light", "point_model") && scene.light.point_model != light.point_model)
    out.emplace_back("light.point_model", "light.point_model is how a point light is traced; a directional light "
                                          "(light.type) ignores it");
  if (point && writes(written, "light", "direction") && scene.light.direction != light.direction)
    out.emplace_back("light.direction", "light.direction aims a directional light; a point light (light.type) "
                                        "shines from light.position, and it is ignored");
  // focus_distance places the screen only where no centre is written.
  if (written.is_object() && written.contains("focus_distance") && !written["focus_distance"].is_null() &&
      writes(written, "screen", "center"))
    out.emplace_back("focus_distance", "focus_distance places the screen when screen.center is absent; "
                                       "screen.center, written too, places it");
  return out;
}

}  // namespace caustic
