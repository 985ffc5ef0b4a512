// SPDX-License-Identifier: LGPL-2.1-or-later
// The solid's keys: object.shape and render.light_grid parsed, bounded and
// written back; a mirror cannot be a solid; a key the shape makes moot is
// warned about; a closed body is what closed_body builds; a water surface
// (object.shape "surface") is glass-like, has no flat face, and is lit from
// outside the medium it bounds.
#include "refusal.hpp"
#include "caustic/spectral.hpp"
#include "caustic/surfaces.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

using namespace caustic;
using namespace caustic::testing;

TEST(SceneShape, ASolidAndItsLightGridRoundTrip) {
  json doc = with("object", "shape", "solid");
  doc["render"]["light_grid"] = 128;
  const Scene s = scene_from_json(doc, ".");
  EXPECT_EQ(s.object.shape, Shape::solid);
  EXPECT_EQ(s.render.light_grid, 128);
  const json back = scene_to_json(s);
  EXPECT_EQ(back["object"]["shape"], "solid");
  EXPECT_EQ(scene_from_json(back, "."), s);
  EXPECT_EQ(scene_from_json(minimal(), ".").object.shape, Shape::slab);
}

TEST(SceneShape, BadShapesAndGridsAreNamed) {
  expect_rejected(with("object", "shape", "sphere"), "object.shape");
  json mirror = with("object", "shape", "solid");
  mirror["object"]["material"] = "reflective";
  expect_rejected(mirror, "object.shape");
  expect_rejected(with("render", "light_grid", 8), "render.light_grid");
  expect_rejected(with("render", "light_grid", 4096), "render.light_grid");
  expect_rejected(with("render", "light_grid", 12.5), "render.light_grid");
  // Resampled on a grid, a closed body came out an open sheet: refused as the
  // mesh ("not a closed surface") when the frame was drawn.
  json gridded = with("object", "shape", "solid");
  gridded["render"] = {{"fidelity", "manual"}, {"mesh_resolution", 64}};
  expect_rejected(gridded, "render.mesh_resolution");
  gridded["render"]["fidelity"] = "auto";  // auto chooses the level, and warns of the one written
  EXPECT_EQ(scene_from_json(gridded, ".").render.mesh_resolution, 64);
}

TEST(SceneShape, KeysTheShapeMakesMootAreWarnedAbout) {
  json solid = with("object", "shape", "solid");
  solid["object"]["flat_face_offset"] = 2.0;
  const auto warned = shape_overrides(solid, scene_from_json(solid, "."));
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_EQ(warned[0].first, "object.flat_face_offset");
  const json slab = with("render", "light_grid", 64);
  const auto moot = shape_overrides(slab, scene_from_json(slab, "."));
  ASSERT_EQ(moot.size(), 1u);
  EXPECT_EQ(moot[0].first, "render.light_grid");
  EXPECT_NE(moot[0].second.find("a slab traces one ray per vertex"), std::string::npos) << moot[0].second;
  // A surface (water) is no slab: the warning said it was.
  json surface = with("render", "light_grid", 64);
  surface["object"]["shape"] = "surface";
  const auto water = shape_overrides(surface, scene_from_json(surface, "."));
  ASSERT_EQ(water.size(), 1u);
  EXPECT_NE(water[0].second.find("a surface traces one ray per vertex"), std::string::npos) << water[0].second;
  // A mirror refracts nothing: its index and its point model were taken
  // without a word (its glass was already said).
  json mirror = with("object", "material", "reflective");
  mirror["object"]["ior"] = 1.7;
  mirror["light"] = {{"type", "point"}, {"point_model", "approximate"}};
  mirror["render"]["fidelity"] = "manual";
  std::vector<std::string> keys;
  for (const auto& [key, detail] : shape_overrides(mirror, scene_from_json(mirror, "."))) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"object.ior", "light.point_model"}));
  mirror["object"]["material"] = "refractive";
  EXPECT_TRUE(shape_overrides(mirror, scene_from_json(mirror, ".")).empty());
  // A complete file writes every key at its value: nothing to say.
  const Scene plain = scene_from_json(with("object", "shape", "solid"), ".");
  EXPECT_TRUE(shape_overrides(scene_to_json(plain), plain).empty());
}

TEST(SceneShape, AMirrorPatchedOntoASolidOrASurfaceNamesTheMaterial) {
  // The merged scene holds its shape: the refusal named object.shape,
  // which the patch never wrote.
  for (const char* shape : {"solid", "surface"}) {
    const Scene s = scene_from_json(with("object", "shape", shape), ".");
    EXPECT_EQ(refusal<SceneError>([&] { apply_merge_patch(s, {{"object", {{"material", "reflective"}}}}); }),
              std::string("object.material: \"reflective\" makes a mirror of a slab's face; this scene's object "
                          "is a ") + shape + " (object.shape \"" + shape +
                  "\"), which light passes through: it must be \"refractive\"");
  }
  // A patch that writes the shape too is answered by the shape, as a file is.
  const Scene slab = scene_from_json(minimal(), ".");
  EXPECT_EQ(refused_key<SceneError>([&] {
              apply_merge_patch(slab, {{"object", {{"material", "reflective"}, {"shape", "solid"}}}});
            }),
            "object.shape");
  EXPECT_EQ(apply_merge_patch(slab, {{"object", {{"material", "reflective"}}}}).object.material, Material::reflective);
}

TEST(SceneShape, ASolidIgnoresTheFlatFaceOffsetWhenPlaced) {
  const Mesh body = biconvex_lens(40, 40, 6, 10, 9);
  ObjectParams o;
  o.shape = Shape::solid;
  o.flat_face_offset = 1.0;  // would cut through the lens
  const Placement p = place_object(o, body);
  EXPECT_NEAR(p.flat_offset, 3.0, 1e-6);  // the upper apex
  EXPECT_NEAR(p.max_depth, 6.0, 1e-6);
}

TEST(SceneShape, ClosedBodyIsClosedAndWoundOutward) {
  const Mesh body = biconvex_lens(40, 40, 6, 10, 17);
  EXPECT_NO_THROW(check_closed(body));
  // Two faces of 17 x 17 and four walls of 2 x 17 vertices.
  EXPECT_EQ(body.positions.size(), 2u * 17 * 17 + 4u * 2 * 17);
  EXPECT_THROW(closed_body(flat_face(1), flat_face(1), 5), std::invalid_argument);
}

TEST(SceneShape, ASurfaceRoundTripsIsRefractiveAndHasNoFlatFace) {
  json water = with("object", "shape", "surface");
  water["object"]["flat_face_offset"] = 2.0;
  const Scene s = scene_from_json(water, ".");
  EXPECT_EQ(s.object.shape, Shape::surface);
  EXPECT_EQ(scene_to_json(s)["object"]["shape"], "surface");
  const auto warned = shape_overrides(water, s);
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_EQ(warned[0].first, "object.flat_face_offset");
  json mirror = with("object", "shape", "surface");
  mirror["object"]["material"] = "reflective";
  expect_rejected(mirror, "object.shape");
  // Placed, the offset is ignored: the plane through the extreme vertex
  // only frames the box.
  ObjectParams o;
  o.shape = Shape::surface;
  o.flat_face_offset = -5.0;  // would cut through the waves
  const Placement p = place_object(o, grid_mesh(sine_window(0.5, 1.0, 0.0, 1.0, 10.0), 33, 33));
  EXPECT_NEAR(p.flat_offset, 0.5, 1e-3);
}

TEST(SceneShape, APointLightInASurfacesMediumIsRefused) {
  // Water 0.5 deep in waves about z = 0, the floor (the screen) 10 below:
  // the medium fills the space beyond the surface, the screen included. A
  // lamp under the water was taken and drew a black frame (each ray sent
  // into the medium away from the floor).
  Scene s = scene_from_json(json{{"mesh", "w.obj"},
                                 {"object", {{"shape", "surface"}}},
                                 {"light", {{"type", "point"}, {"position", {0, 0, 20}}}},
                                 {"screen", {{"center", {0, 0, -10}}, {"width", 20}, {"height", 20}}}},
                            ".");
  const Mesh waves = grid_mesh(sine_window(0.5, 1.0, 0.0, 1.0, 10.0), 33, 33);
  const Placement p = place_object(s.object, waves);
  const auto said = [&](const glm::dvec3& light) {
    Scene lit = s;
    lit.light.position = light;
    const std::string why = refusal<SceneError>([&] { check_geometry(lit, waves, p); });
    // The public check (the proxy box alone) says the same.
    EXPECT_EQ(why, refusal<SceneError>([&] { check_geometry_public(lit, p); }));
    return why;
  };
  EXPECT_EQ(said({0, 0, 20}), "accepted");
  EXPECT_EQ(said({30, 0, 3}), "accepted");  // beside the pool, above its waves
  for (const glm::dvec3& in_water : {glm::dvec3(0, 0, -3), glm::dvec3(0, 0, -20), glm::dvec3(40, 0, -1)})
    EXPECT_EQ(said(in_water).rfind("light.position: the point light lies on the screen's side of the surface", 0), 0u)
        << in_water.z;
  EXPECT_EQ(said({0, 0, 0.2}).rfind("light.position: the point light lies level with the surface's relief", 0), 0u);
  EXPECT_EQ(said({40, 0, 0.2}).rfind("light.position: the point light lies level with the surface's relief", 0), 0u);
  // Lit from below with the screen above, the medium is above: taken.
  s.screen.center = {0, 0, 10};
  EXPECT_EQ(said({0, 0, -20}), "accepted");
  EXPECT_NE(said({0, 0, 20}).find("on the screen's side"), std::string::npos);
}
