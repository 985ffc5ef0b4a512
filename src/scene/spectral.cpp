// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/spectral.hpp"

#include <cmath>
#include <optional>

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
  const auto grid = written_number(written, "render", "light_grid");
  if (!solid && grid && *grid != RenderParams{}.light_grid)
    out.emplace_back("render.light_grid", "render.light_grid sizes the light's grid for a solid (object.shape "
                                          "\"solid\"); a slab traces one ray per vertex of its face instead");
  return out;
}

}  // namespace caustic
