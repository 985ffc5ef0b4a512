// SPDX-License-Identifier: LGPL-2.1-or-later
// The scene's `water` section in JSON (caustic/water_params.hpp), kept apart
// from scene_json.cpp, which calls it for that one key.
#pragma once

#include "caustic/water_params.hpp"
#include "json_reader.hpp"

namespace caustic::detail {

/// Reads and checks the section (validate() included); throws SceneError
/// naming "water.<key>".
water::WaveParams read_water(Reader r);
nlohmann::json water_to_json(const water::WaveParams& water);

}  // namespace caustic::detail
