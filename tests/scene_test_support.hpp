// SPDX-License-Identifier: LGPL-2.1-or-later
// Building scene documents and expecting their rejection, for the scene
// tests.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace caustic::testing {

using nlohmann::json;

inline json minimal() { return json{{"mesh", "m.obj"}}; }

// Expects the document to be rejected with a message that names `key`.
inline void expect_rejected(const json& doc, const std::string& key) {
  try {
    scene_from_json(doc, ".");
    ADD_FAILURE() << "accepted: " << doc.dump();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

// Expects the scene, posed over `face`, to be refused by check_geometry
// naming `key`.
inline void expect_geometry_refused(const Scene& scene, const Mesh& face, const std::string& key) {
  try {
    check_geometry(scene, face, place_object(scene.object, face));
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
  }
}

inline json with(const std::string& section, const std::string& key, json value) {
  json doc = minimal();
  doc[section][key] = std::move(value);
  return doc;
}

}  // namespace caustic::testing
