// SPDX-License-Identifier: LGPL-2.1-or-later
// The solid's keys: object.shape and render.light_grid parsed, bounded and
// written back; a mirror cannot be a solid; a key the shape makes moot is
// warned about; a closed body is what closed_body builds; a water surface
// (object.shape "surface") is glass-like and has no flat face.
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
  // A complete file writes every key at its value: nothing to say.
  const Scene plain = scene_from_json(with("object", "shape", "solid"), ".");
  EXPECT_TRUE(shape_overrides(scene_to_json(plain), plain).empty());
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
