// SPDX-License-Identifier: LGPL-2.1-or-later
// object.glass in JSON: a catalogue name ("bk7") or a law's coefficients,
// {"sellmeier": {"b": [...], "c": [...]}} or {"cauchy": {"a": 1.5, "b": 0.004}}
// (λ in µm, as the laws are written). Kept apart from scene_json.cpp, which
// calls it for that one key.
#pragma once

#include "caustic/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace caustic {

/// Parses and checks a glass: a known name, or coefficients giving an index
/// in [1, 10] at every nanometre of the visible range (no pole in it).
/// Throws SceneError naming `key` (or the coefficient under it).
Glass glass_from_json(const nlohmann::json& j, const std::string& key);
/// The name when it has one, else the coefficients.
nlohmann::json glass_to_json(const Glass& glass);

}  // namespace caustic
