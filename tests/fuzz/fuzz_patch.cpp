// SPDX-License-Identifier: LGPL-2.1-or-later
// apply_merge_patch is what PATCH /sessions/{id}/params runs on a live
// scene. A patch may be refused (SceneError); one that is taken must leave a
// scene a renderer can use: valid, and with no NaN or Inf anywhere.
#include "caustic/json_text.hpp"
#include "caustic/scene.hpp"
#include "fuzz_support.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>

namespace {

using nlohmann::json;

// Like assets/scenes/lens.json, the scene most sessions start from.
caustic::Scene lens_scene() {
  caustic::Scene s;
  s.name = "Plano-convex lens";
  s.description = "A spherical plano-convex lens under parallel light.";
  s.mesh = "../meshes/lens.obj";
  s.base_dir = "/nonexistent/scenes";
  s.focus_distance = 80.0;
  s.object.flat_face_offset = 4.0;
  s.screen.center = s.object.position - 80.0 * s.screen.normal;
  s.screen.width = 24;
  s.screen.height = 24;
  s.post.exposure = 0.5;
  s.post.bloom_threshold = 4.0;
  s.post.bloom_strength = 0.4;
  s.post.bloom_radius = 12;
  return s;
}

bool all_finite(const json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_structured())
    for (const auto& child : j)
      if (!all_finite(child)) return false;
  return true;
}

const caustic::Scene& base() {
  static const caustic::Scene scene = [] {
    caustic::Scene s = lens_scene();
    caustic::validate_scene(s);  // a broken base would make every input look bad
    return s;
  }();
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto patch = caustic::parse_json_text(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!patch) return -1;
  const caustic::Scene before = base();
  caustic::Scene patched;
  try {
    patched = caustic::apply_merge_patch(base(), *patch);
  } catch (const caustic::SceneError& e) {
    FUZZ_CHECK(base() == before);
    return 0;
  }
  FUZZ_CHECK(base() == before);
  FUZZ_CHECK(patched.base_dir == before.base_dir);
  FUZZ_CHECK(all_finite(caustic::scene_to_json(patched)));
  try {
    caustic::validate_scene(patched);
  } catch (const caustic::SceneError& e) {
    std::fprintf(stderr, "patched scene does not validate: %s\n", e.what());
    FUZZ_CHECK(!"a patched scene validates");
  }
  return 0;
}
