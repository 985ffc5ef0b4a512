// SPDX-License-Identifier: LGPL-2.1-or-later
// Numbers a scene or a --set assignment writes beyond what they hold: a
// whole number past 2^64 (held as a double), a number past a double's range
// (1e400): each said as what it is, naming the key.
#include "refusal.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

using namespace caustic;
using namespace caustic::testing;

TEST(SceneNumbers, AWholeNumberPastTwoToTheSixtyFourIsOutOfRangeNotNoInteger) {
  // 10^23 is parsed as a double: it was refused as "must be an integer".
  const json huge = json::parse(R"({"mesh": "m.obj", "render": {"light_grid": 99999999999999999999999}})");
  const std::string why = refusal<SceneError>([&] { scene_from_json(huge, "."); });
  EXPECT_EQ(why.rfind("render.light_grid: must be in [16, 2048], got 9.99", 0), 0u) << why;
  EXPECT_EQ(refusal<SceneError>([&] { scene_from_json(with("render", "width", -1e30), "."); }),
            "render.width: must be in [16, 8192], got -1e+30");
  // A fraction, or a whole number written as a float within the range, is still no integer.
  EXPECT_EQ(refusal<SceneError>([&] { scene_from_json(with("render", "light_grid", 64.5), "."); }),
            "render.light_grid: must be an integer");
  EXPECT_EQ(refusal<SceneError>([&] { scene_from_json(with("render", "light_grid", 64.0), "."); }),
            "render.light_grid: must be an integer");
}

TEST(SceneNumbers, AnAssignedNumberPastADoublesRangeIsSaidAsThat) {
  // Not JSON, it was taken as the string written and refused as "must be a number".
  for (const char* value : {"1e400", "-1e400", " 2E+999"}) {
    const std::string why = refusal<SceneError>([&] { patch_from_assignment(std::string("object.ior=") + value); });
    EXPECT_EQ(why.rfind("object.ior: not valid JSON: a number beyond the range of a double", 0), 0u)
        << value << ": " << why;
  }
  // What is no number stays the string written, for the key to judge.
  for (const char* text : {"1.5.", "1e", "NaN", "+1", ".5", "01x", "bk7"})
    EXPECT_EQ(patch_from_assignment(std::string("object.glass=") + text), (json{{"object", {{"glass", text}}}}))
        << text;
  EXPECT_EQ(patch_from_assignment("object.ior=-0.5e-3"), (json{{"object", {{"ior", -0.5e-3}}}}));
}
