// SPDX-License-Identifier: LGPL-2.1-or-later
// What a spectral frame traces: one pass per wavelength sample, each with
// the glass's index there and the band's white-balanced RGB weight
// (caustic/colour.hpp). Renderers add the passes' irradiance times their
// weights; without dispersion every pass would take the same path, so the
// frame is monochrome and no list is made.
#pragma once

#include "caustic/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace caustic {

struct SpectralPass {
  double nm = 0;
  double ior = 1.5;
  optics::Rgb weight;
};

/// Whether the scene renders in colour: a refractive object of a glass.
bool spectral(const Scene& scene);

/// The passes of a frame of `count` wavelengths (render.wavelengths, or
/// fewer for a preview); empty when the scene is not spectral.
std::vector<SpectralPass> spectral_passes(const Scene& scene, int count);

/// The wavelengths a frame of the scene samples: at most
/// kPreviewWavelengths for a preview (the scene moving), render.wavelengths
/// for a full frame, and render.still_wavelengths where that is more for a
/// picture left standing; 0 when the scene is not spectral. The one rule
/// the engine draws by and the stream decides its still spells by.
int frame_wavelengths(const Scene& scene, bool preview, bool still);

/// Throws SceneError naming render.light_grid or render.mesh_resolution
/// when a frame of `scene` would trace more than kMaxFrameRays (a solid's
/// light_grid², or a manual mesh level's n², times its still frame's
/// wavelengths). scene_from_json calls it on every scene read or patched.
void check_frame_cost(const Scene& scene);

/// Keys that `written` (a scene file or a patch) sets but that the spectral
/// settings of `scene` (the result) override or make moot, each with a
/// sentence for its writer: object.ior beside object.glass, light
/// temperature_k without a blackbody, a glass on a mirror, and
/// render.wavelengths or light.spectrum without a glass (a grey frame).
/// Values equal to the defaults are not reported: a complete scene file
/// writes every key.
std::vector<std::pair<std::string, std::string>> spectral_overrides(const nlohmann::json& written, const Scene& scene);

/// The same for the object's shape and material (kept beside the spectral
/// ones, whose readers of `written` it shares): object.flat_face_offset on a
/// solid, which has no flat face, render.light_grid on a slab, whose rays
/// start at its vertices, and object.ior and light.point_model on a mirror,
/// which refracts nothing.
std::vector<std::pair<std::string, std::string>> shape_overrides(const nlohmann::json& written, const Scene& scene);

/// The same for keys that a setting of their own section leaves unused:
/// render.report_plane_distance without intensity "report",
/// render.accuracy_target with fidelity "manual", post.local_strength with
/// the global tone map, post.auto_percentile and exposure_adapt_s with a
/// manual exposure, post.bloom_radius and bloom_threshold without bloom,
/// light.position and point_model on a directional light, light.direction
/// on a point light, and focus_distance beside a written screen.center.
std::vector<std::pair<std::string, std::string>> setting_overrides(const nlohmann::json& written, const Scene& scene);

}  // namespace caustic
