// SPDX-License-Identifier: LGPL-2.1-or-later
// scene_from_json on any JSON value: a SceneError is the expected answer to
// bad input; any other exception escapes and crashes the run. An accepted
// scene must survive what the server does next with it: validation, and a
// trip through its own JSON text.
#include "caustic/json_text.hpp"
#include "caustic/scene.hpp"
#include "fuzz_support.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto value = caustic::parse_json_text(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!value) return -1;  // not JSON: nothing for scene_from_json to see, keep it out of the corpus
  caustic::Scene scene;
  try {
    scene = caustic::scene_from_json(*value, "/nonexistent/scenes");
  } catch (const caustic::SceneError& e) {
    FUZZ_CHECK(*e.what() != '\0');
    return 0;
  }
  try {
    caustic::validate_scene(scene);
    const auto text = caustic::dump_json(caustic::scene_to_json(scene));
    const auto reparsed = caustic::parse_json_text(text);
    FUZZ_CHECK(reparsed.has_value());
    caustic::scene_from_json(*reparsed, scene.base_dir, scene.receiver_meshes);
  } catch (const caustic::SceneError& e) {
    std::fprintf(stderr, "accepted scene does not validate: %s\n", e.what());
    FUZZ_CHECK(!"an accepted scene validates");
  }
  return 0;
}
