// SPDX-License-Identifier: LGPL-2.1-or-later
// The spectral keys: object.glass by name or coefficients, light.spectrum
// and temperature_k, render.wavelengths and still_wavelengths; bad values named, the overridden
// ones warned about, how many wavelengths a frame samples and the passes it traces.
#include "refusal.hpp"
#include "caustic/spectral.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

using namespace caustic;
using namespace caustic::testing;

TEST(SceneSpectral, AGlassByNameSetsTheIndexAtTheDLine) {
  const Scene s = scene_from_json(with("object", "glass", "bk7"), ".");
  ASSERT_TRUE(s.object.glass);
  EXPECT_EQ(s.object.glass->name, "bk7");
  EXPECT_NEAR(s.object.ior, 1.5168, 1e-4);  // SCHOTT N-BK7 n_d
  EXPECT_TRUE(spectral(s));
  const json back = scene_to_json(s);
  EXPECT_EQ(back["object"]["glass"], "bk7");
  EXPECT_EQ(scene_from_json(back, "."), s);
  // "none" removes it where a patch's null would restore it.
  const Scene none = apply_merge_patch(s, json{{"object", {{"glass", "none"}}}});
  EXPECT_FALSE(none.object.glass);
  EXPECT_FALSE(spectral(none));
  EXPECT_TRUE(scene_to_json(none)["object"]["glass"].is_null());
}

TEST(SceneSpectral, CoefficientsRoundTrip) {
  const json sellmeier = {{"sellmeier", {{"b", {1.03961212, 0.231792344, 1.01046945}},
                                         {"c", {0.00600069867, 0.0200179144, 103.560653}}}}};
  const Scene s = scene_from_json(with("object", "glass", sellmeier), ".");
  EXPECT_TRUE(s.object.glass->name.empty());
  EXPECT_NEAR(s.object.ior, 1.5168, 1e-4);  // the same N-BK7 law, written out
  EXPECT_EQ(scene_from_json(scene_to_json(s), "."), s);

  const Scene c = scene_from_json(with("object", "glass", {{"cauchy", {{"a", 1.5}, {"b", 0.0042}}}}), ".");
  EXPECT_NEAR(c.object.glass->index(500), 1.5 + 0.0042 / 0.25, 1e-12);
  EXPECT_EQ(scene_from_json(scene_to_json(c), "."), c);
}

TEST(SceneSpectral, BadGlassesAreNamed) {
  expect_rejected(with("object", "glass", "unobtainium"), "object.glass");
  expect_rejected(with("object", "glass", 1.5), "object.glass");
  expect_rejected(with("object", "glass", json::object()), "object.glass");
  expect_rejected(with("object", "glass", {{"sellmeier", {{"b", {1.0}}}}}), "object.glass.sellmeier");
  expect_rejected(with("object", "glass", {{"sellmeier", {{"b", {1.0}}, {"c", {0.01, 0.02}}}}}),
                  "object.glass.sellmeier.c");
  expect_rejected(with("object", "glass", {{"sellmeier", {{"b", {1, 1, 1, 1, 1}}, {"c", {0, 0, 0, 0, 0}}}}}),
                  "object.glass.sellmeier.b");
  expect_rejected(with("object", "glass", {{"sellmeier", {{"b", {-1.0}}, {"c", {0.01}}}}}),
                  "object.glass.sellmeier.b");
  // A pole at 500 nm (c = 0.25 µm²) lies in the visible: no index there.
  expect_rejected(with("object", "glass", {{"sellmeier", {{"b", {1.0}}, {"c", {0.25}}}}}), "object.glass");
  expect_rejected(with("object", "glass", {{"cauchy", {{"a", 0.5}, {"b", 0.0}}}}), "object.glass.cauchy.a");
  expect_rejected(with("object", "glass", {{"cauchy", {{"a", 1.5}, {"b", "x"}}}}), "object.glass.cauchy.b");
  expect_rejected(with("object", "glass", {{"cauchy", {{"a", 1.5}, {"b", 0.0}, {"z", 1}}}}), "object.glass.cauchy.z");
  expect_rejected(with("object", "glass", {{"cauchy", {{"a", 1.5}, {"b", 0.0}}}, {"sellmeier", 1}}),
                  "object.glass");
  expect_rejected(with("light", "spectrum", "sodium"), "light.spectrum");
  expect_rejected(with("light", "temperature_k", 500), "light.temperature_k");
  expect_rejected(with("render", "wavelengths", 0), "render.wavelengths");
  expect_rejected(with("render", "wavelengths", 33), "render.wavelengths");
  expect_rejected(with("render", "still_wavelengths", 0), "render.still_wavelengths");
  expect_rejected(with("render", "still_wavelengths", 33), "render.still_wavelengths");
  expect_rejected(with("render", "still_wavelengths", 12.5), "render.still_wavelengths");
  // Beyond 64 bits signed: said as written, not wrapped to -1.
  try {  // the message quotes the number as written
    scene_from_json(with("render", "still_wavelengths", 18446744073709551615ull), ".");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "render.still_wavelengths");
    EXPECT_NE(std::string(e.what()).find("got 18446744073709551615"), std::string::npos) << e.what();
  }
}

TEST(SceneSpectral, StillWavelengthsRoundTrip) {
  json doc = with("object", "glass", "bk7");
  doc["render"]["still_wavelengths"] = 12;
  const Scene s = scene_from_json(doc, ".");
  EXPECT_EQ(s.render.still_wavelengths, 12);
  EXPECT_EQ(scene_to_json(s)["render"]["still_wavelengths"], 12);
  EXPECT_EQ(scene_from_json(scene_to_json(s), "."), s);
  EXPECT_EQ(scene_from_json(minimal(), ".").render.still_wavelengths, 32);  // the most a frame may sample
}

TEST(SceneSpectral, AFrameSamplesFewWhileMovingAndMoreLeftStanding) {
  json doc = with("object", "glass", "bk7");
  doc["render"]["wavelengths"] = 8;
  doc["render"]["still_wavelengths"] = 24;
  Scene s = scene_from_json(doc, ".");
  EXPECT_EQ(frame_wavelengths(s, true, false), kPreviewWavelengths);
  EXPECT_EQ(frame_wavelengths(s, true, true), kPreviewWavelengths) << "a preview is never a picture left standing";
  EXPECT_EQ(frame_wavelengths(s, false, false), 8);
  EXPECT_EQ(frame_wavelengths(s, false, true), 24);
  // Fewer still wavelengths than a frame's (warned about) never thin it;
  // fewer frame wavelengths than a preview's are not raised to it.
  s.render.still_wavelengths = 4;
  EXPECT_EQ(frame_wavelengths(s, false, true), 8);
  s.render.wavelengths = 2;
  EXPECT_EQ(frame_wavelengths(s, true, false), 2);
  // A grey scene samples none: a picture left standing draws nothing more.
  EXPECT_EQ(frame_wavelengths(scene_from_json(minimal(), "."), false, true), 0);
}

TEST(SceneSpectral, PassesFollowTheGlassAndTheLight) {
  json doc = with("object", "glass", "bk7");
  doc["render"]["wavelengths"] = 4;
  doc["light"] = {{"spectrum", "blackbody"}, {"temperature_k", 3000}};
  const Scene s = scene_from_json(doc, ".");
  const auto passes = spectral_passes(s, s.render.wavelengths);
  ASSERT_EQ(passes.size(), 4u);
  for (std::size_t i = 1; i < passes.size(); ++i) {
    EXPECT_GT(passes[i].nm, passes[i - 1].nm);
    EXPECT_LT(passes[i].ior, passes[i - 1].ior) << "normal dispersion: red bends least";
  }
  // A mirror, or no glass: one grey pass, no list.
  Scene mirror = s;
  mirror.object.material = Material::reflective;
  EXPECT_TRUE(spectral_passes(mirror, 4).empty());
  EXPECT_TRUE(spectral_passes(scene_from_json(minimal(), "."), 4).empty());
}

TEST(SceneSpectral, KeysThatAnotherSettingOverridesAreWarnedAbout) {
  json doc = with("object", "glass", "bk7");
  doc["object"]["ior"] = 1.7;
  doc["light"]["temperature_k"] = 3000;  // the default spectrum is D65
  const Scene s = scene_from_json(doc, ".");
  EXPECT_NEAR(s.object.ior, 1.5168, 1e-4);
  const auto warned = spectral_overrides(doc, s);
  ASSERT_EQ(warned.size(), 2u);
  EXPECT_EQ(warned[0].first, "object.ior");
  EXPECT_EQ(warned[1].first, "light.temperature_k");

  doc["object"]["material"] = "reflective";
  const auto mirror = spectral_overrides(doc, scene_from_json(doc, "."));
  EXPECT_EQ(mirror.size(), 3u);
  EXPECT_EQ(mirror[1].first, "object.glass");

  // Without a glass, what shapes a spectral frame is moot.
  const json grey = {{"mesh", "m.obj"}, {"light", {{"spectrum", "led"}}}, {"render", {{"wavelengths", 16}}}};
  const auto moot = spectral_overrides(grey, scene_from_json(grey, "."));
  ASSERT_EQ(moot.size(), 2u);
  EXPECT_EQ(moot[0].first, "render.wavelengths");
  EXPECT_EQ(moot[1].first, "light.spectrum");
  EXPECT_TRUE(spectral_overrides(scene_to_json(scene_from_json(minimal(), ".")), scene_from_json(minimal(), ".")).empty());
  const json grey_still = {{"mesh", "m.obj"}, {"render", {{"still_wavelengths", 16}}}};
  const auto moot_still = spectral_overrides(grey_still, scene_from_json(grey_still, "."));
  ASSERT_EQ(moot_still.size(), 1u);
  EXPECT_EQ(moot_still[0].first, "render.still_wavelengths");
  // Fewer when still than when not: the picture left standing keeps the more.
  json fewer = with("object", "glass", "bk7");
  fewer["render"] = {{"wavelengths", 16}, {"still_wavelengths", 8}};
  const auto kept = spectral_overrides(fewer, scene_from_json(fewer, "."));
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].first, "render.still_wavelengths");
  EXPECT_NE(kept[0].second.find("(16)"), std::string::npos) << kept[0].second;
  // A complete scene file, as scene_to_json writes it, says nothing twice.
  const Scene glass = scene_from_json(with("object", "glass", "bk7"), ".");
  EXPECT_TRUE(spectral_overrides(scene_to_json(glass), glass).empty());
  // Written where it counts, nothing to say.
  const json fine = {{"mesh", "m.obj"}, {"object", {{"glass", "water"}}}, {"light", {{"spectrum", "blackbody"}, {"temperature_k", 3000}}}};
  EXPECT_TRUE(spectral_overrides(fine, scene_from_json(fine, ".")).empty());
}

TEST(SceneSpectral, KeysTheirOwnSectionLeavesUnusedAreWarnedAbout) {
  const auto keys = [](const json& doc) {
    std::vector<std::string> out;
    for (const auto& [key, detail] : setting_overrides(doc, scene_from_json(doc, "."))) out.push_back(key);
    return out;
  };
  json doc = minimal();
  doc["render"] = {{"report_plane_distance", 2.0}, {"fidelity", "manual"}, {"accuracy_target", 0.1}};
  doc["post"] = {{"local_strength", 0.9}, {"exposure_mode", "manual"}, {"auto_percentile", 0.9},
                 {"exposure_adapt_s", 2.0}};
  doc["focus_distance"] = 50;
  doc["screen"] = {{"center", {0, 0, -70}}};
  EXPECT_EQ(keys(doc), (std::vector<std::string>{"render.report_plane_distance", "render.accuracy_target",
                                                 "post.local_strength", "post.auto_percentile",
                                                 "post.exposure_adapt_s", "focus_distance"}));
  // Where each is used, nothing to say; nor for defaults written out.
  json used = minimal();
  used["render"] = {{"intensity", "report"}, {"report_plane_distance", 2.0}, {"accuracy_target", 0.1}};
  used["post"] = {{"tone_map", "local"}, {"local_strength", 0.9}, {"auto_percentile", 0.9}, {"exposure_adapt_s", 2.0}};
  used["focus_distance"] = 50;
  EXPECT_TRUE(keys(used).empty());
  const Scene plain = scene_from_json(minimal(), ".");
  EXPECT_TRUE(setting_overrides(scene_to_json(plain), plain).empty());
  // The light's keys of the other kind, and a bloom of strength 0.
  json directional = minimal();
  directional["light"] = {{"type", "directional"}, {"position", {5, 5, 50}}, {"point_model", "approximate"}};
  directional["post"] = {{"bloom_strength", 0.0}, {"bloom_radius", 4.0}, {"bloom_threshold", 2.0}};
  EXPECT_EQ(keys(directional), (std::vector<std::string>{"post.bloom_radius", "post.bloom_threshold",
                                                         "light.position", "light.point_model"}));
  json point = minimal();
  point["light"] = {{"type", "point"}, {"position", {0, 0, 120}}, {"direction", {0, 0.2, -1}}};
  EXPECT_EQ(keys(point), std::vector<std::string>{"light.direction"});
  point["light"].erase("direction");
  point["light"]["point_model"] = "approximate";
  point["post"] = {{"bloom_radius", 4.0}};
  EXPECT_TRUE(keys(point).empty());
}

TEST(SceneSpectral, AFrameMayTraceABoundedNumberOfRays) {
  // 2048² rays at 32 wavelengths would take a software renderer about 90 s
  // a frame, and past stall_timeout_s the server's watchdog. Counted from the public
  // grid sizes and the still frame's wavelengths.
  json solid = minimal();
  solid["object"] = {{"shape", "solid"}, {"glass", "bk7"}};
  solid["render"] = {{"light_grid", 2048}};  // 32 still wavelengths by default
  expect_rejected(solid, "render.light_grid");
  solid["render"] = {{"light_grid", 2048}, {"wavelengths", 2}, {"still_wavelengths", 2}};
  EXPECT_NO_THROW(scene_from_json(solid, ".")) << "2048² rays at 2 wavelengths is within the bound";
  solid["object"].erase("glass");
  solid["render"] = {{"light_grid", 2048}};
  EXPECT_NO_THROW(scene_from_json(solid, ".")) << "grey: one wavelength";
  json slab = with("object", "glass", "bk7");
  slab["render"] = {{"fidelity", "manual"}, {"mesh_resolution", 2048}};
  expect_rejected(slab, "render.mesh_resolution");
  slab["render"] = {{"fidelity", "auto"}, {"mesh_resolution", 2048}};
  EXPECT_NO_THROW(scene_from_json(slab, ".")) << "auto chooses the level itself";
  slab["render"] = {{"fidelity", "manual"}, {"mesh_resolution", 0}};
  EXPECT_NO_THROW(scene_from_json(slab, ".")) << "the loaded mesh is the operator's (and its size a secret)";
  slab["render"] = {{"fidelity", "manual"}, {"mesh_resolution", 512}};
  EXPECT_NO_THROW(scene_from_json(slab, ".")) << "512² at 32 wavelengths is the bound itself";
  // A curved receiver costs each ray a search of its triangles (seven lathes
  // once took such a frame from 5 s to 65): it counts as two rays.
  slab["receivers"] = {{{"center", {40, 0, -30}}, {"normal", {-1, 0, 0}}, {"up", {0, 0, 1}},
                        {"lathe", {{"profile", {{5, 0}, {8, 10}, {4, 30}}}, {"segments", 48}}}}};
  const std::string why = caustic::testing::refusal<SceneError>([&] { scene_from_json(slab, "."); });
  EXPECT_EQ(why.rfind("render.mesh_resolution: ", 0), 0u) << why;
  EXPECT_NE(why.find("1 curved receiver"), std::string::npos) << why;
  slab["render"] = {{"fidelity", "manual"}, {"mesh_resolution", 256}};
  EXPECT_NO_THROW(scene_from_json(slab, ".")) << "256² at 32 wavelengths onto one lathe: 3 x 2^21 rays' work";
}
