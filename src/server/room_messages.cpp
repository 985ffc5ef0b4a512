// SPDX-License-Identifier: LGPL-2.1-or-later
#include "room_messages.hpp"

#include "caustic/receivers.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace caustic::server {
namespace {

// Every number of `j` to 1 / `per_unit` (a power of ten): 3.3000000000000003
// to 1e-4 is written "3.3" (a division by the power, not a product with its
// inverse, gives the double nearest the short decimal).
nlohmann::json rounded(nlohmann::json j, double per_unit) {
  if (j.is_number_float()) {
    const double v = std::round(j.get<double>() * per_unit) / per_unit;
    // A whole number as an integer: "3", not "3.0".
    if (v == std::floor(v) && std::abs(v) < 1e15) return static_cast<std::int64_t>(v);
    return v;
  }
  if (j.is_structured())
    for (auto& item : j) item = rounded(std::move(item), per_unit);
  return j;
}

nlohmann::json tile_json(const AtlasTile& t) {
  return {{"x", t.x}, {"y", t.y}, {"width", t.width}, {"height", t.height}};
}

}  // namespace

std::vector<std::string> room_messages(const Scene& scene, std::uint64_t version) {
  const nlohmann::json j = scene_to_json(scene);
  const std::size_t count = scene.receivers.size();
  const auto tiles = atlas_layout(scene.render.width, scene.render.height, 1 + count);
  nlohmann::json room = {{"light", j.at("light")}, {"screen", j.at("screen")}, {"object", nlohmann::json::object()}};
  for (const char* key : {"position", "rotation_deg", "ior"}) room["object"][key] = j.at("object").at(key);
  // A pool's viewers draw its surface at its size (heights come with each frame).
  if (scene.water) room["water"] = {{"size", scene.water->size}};
  room["render"] = {{"width", scene.render.width}, {"height", scene.render.height}};
  room["receiver_count"] = count;
  room["tile"] = tile_json(tiles.at(0));
  std::vector<std::string> out{nlohmann::json{{"params", room}, {"version", version}}.dump()};
  const nlohmann::json& receivers = j.at("receivers");
  for (std::size_t i = 0; i < count; ++i) {
    // To 1e-4, or coarser where a profile of large numbers needs it: at
    // whole units the largest the format allows fits.
    std::string text;
    for (double per_unit : {1e4, 1e3, 1e2, 1e1, 1.0}) {
      text = nlohmann::json{{"receiver",
                             {{"index", i}, {"count", count}, {"tile", tile_json(tiles.at(1 + i))},
                              {"surface", rounded(receivers.at(i), per_unit)}}},
                            {"version", version}}
                 .dump();
      if (text.size() <= kRoomDatagramBytes) break;
    }
    out.push_back(std::move(text));
  }
  return out;
}

}  // namespace caustic::server
