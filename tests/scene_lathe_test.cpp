// SPDX-License-Identifier: LGPL-2.1-or-later
// A lathe among the receivers: parsed, written back, bad ones named by
// their key; its mesh's atlas, stretch and seam; rays landing on it against
// the analytic cylinder, and its hierarchy against every triangle tried.
#include "caustic/receivers.hpp"
#include "caustic/surfaces.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace caustic;
using namespace caustic::testing;

namespace {

// A vase standing on the floor beside the slab: 5 mm at its foot, 8 at its
// belly, 4 at its neck, 30 tall.
json vase() {
  return {{"center", {40, 0, -30}}, {"normal", {-1, 0, 0}}, {"up", {0, 0, 1}},
          {"lathe", {{"profile", {{5, 0}, {8, 10}, {4, 30}}}, {"segments", 48}}}};
}

json floor_rectangle() {
  return {{"center", {0, 0, -30}}, {"normal", {0, 0, 1}}, {"up", {0, 1, 0}}, {"width", 50}, {"height", 40}};
}

}  // namespace

TEST(SceneLathe, ParsesAndRoundTrips) {
  json doc = minimal();
  doc["receivers"] = {floor_rectangle(), vase()};
  const Scene s = scene_from_json(doc, ".");
  ASSERT_TRUE(s.receivers[1].lathe);
  const Lathe& l = *s.receivers[1].lathe;
  EXPECT_EQ(l.profile.size(), 3u);
  EXPECT_EQ(l.segments, 48);
  EXPECT_EQ(s.receivers[1].width, 1.0);  // its tile is its (u, v) square
  EXPECT_EQ(l.mesh->triangle_count(), 2u * 48 * 2);
  const json back = scene_to_json(s);
  EXPECT_FALSE(back["receivers"][1].contains("width"));
  EXPECT_EQ(scene_from_json(back, "."), s);
  EXPECT_TRUE(has_shaped_receiver(s));
  EXPECT_FALSE(has_shaped_receiver(scene_from_json(minimal(), ".")));
}

TEST(SceneLathe, BadLathesAreNamed) {
  json doc = minimal();
  const auto with = [&](const std::string& key, const json& value) {
    json v = vase();
    v["lathe"][key] = value;
    doc["receivers"] = {v};
  };
  with("profile", json::array({{5, 0}}));  // one point
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("profile", json::array({{-1, 0}, {5, 3}}));  // a negative radius
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("profile", json::array({{0, 0}, {0, 3}}));  // on the axis: no area
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("profile", json::array({{4, 2}, {4, 2}, {4, 2}}));  // one point: no area either (it was taken)
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("profile", json::array({{1, 0}, {2, "3"}}));
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("profile", json::array({{1, 0}, {2, 3, 4}}));
  expect_rejected(doc, "receivers[0].lathe.profile");
  json many = json::array();
  for (int i = 0; i < 65; ++i) many.push_back({5, i});
  with("profile", many);
  expect_rejected(doc, "receivers[0].lathe.profile");
  with("segments", 2);
  expect_rejected(doc, "receivers[0].lathe.segments");
  with("segments", 100000);
  expect_rejected(doc, "receivers[0].lathe.segments");
  with("colour", "white");
  expect_rejected(doc, "receivers[0].lathe.colour");
  json sized = vase();
  sized["width"] = 10;  // a lathe's size is its profile
  doc["receivers"] = {sized};
  expect_rejected(doc, "receivers[0].width");
  doc["receivers"] = json::array();
  doc["screen"] = vase();
  expect_rejected(doc, "screen.lathe");
}

TEST(SceneLathe, OneReachingIntoTheObjectIsRefused) {
  json doc = minimal();
  json v = vase();
  v["center"] = {0, 0, -10};  // standing under the slab, its neck through it
  doc["receivers"] = {v};
  const Scene s = scene_from_json(doc, ".");
  const Mesh face = grid_mesh(sine_window(0.5, 1.0, 0.5, 1.0, 5), 9, 9);
  expect_geometry_refused(s, face, "receivers[0].lathe");
}

TEST(SceneLathe, ARayLandsOnTheCylinderWhereGeometrySays) {
  // A cylinder of radius 10 about z from the origin, 64 facets: a ray along
  // -x at height 7, turned half a step toward +y, meets facet 0 in its middle.
  const ReceiverMesh c = make_lathe({{10, 0}, {10, 20}}, 64, {0, 0, 0}, {1, 0, 0}, {0, 0, 1});
  const double apothem = 10 * std::cos(std::numbers::pi / 64);
  // Straight at the middle of facet 0 (its normal at half a step round).
  const double half = std::numbers::pi / 64;
  const glm::dvec3 toward(std::cos(half), std::sin(half), 0);
  const auto hit = c.intersect(100.0 * toward + glm::dvec3(0, 0, 7), -toward, 1e9);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 100 - apothem, 1e-9);
  EXPECT_NEAR(hit->uv.x, 0.5 / 64, 1e-9);
  EXPECT_NEAR(hit->uv.y, 7.0 / 20, 1e-9);
  // Every facet: 2 r sin(pi / n) x 20 mm of world on 1/n x 1 of atlas.
  EXPECT_NEAR(c.stretch(hit->element), 2 * 10 * std::sin(half) * 20 * 64, 1e-9);
  // Nothing nearer than `before`; above the rim or beside it, nothing.
  EXPECT_FALSE(c.intersect(100.0 * toward + glm::dvec3(0, 0, 7), -toward, 50));
  EXPECT_FALSE(c.intersect({100, 0, 25}, {-1, 0, 0}, 1e9));
  EXPECT_FALSE(c.intersect({100, 0, 7}, {1, 0, 0}, 1e9));
  // Across the seam the atlas is cut: facet 0 and facet 63 share points, not corners.
  const auto left = c.intersect({100, 0.5, 7}, {-1, 0, 0}, 1e9), right = c.intersect({100, -0.5, 7}, {-1, 0, 0}, 1e9);
  ASSERT_TRUE(left && right);
  EXPECT_LT(left->uv.x, 0.02);
  EXPECT_GT(right->uv.x, 0.98);
  EXPECT_FALSE(c.continuous(left->element, right->element));
  const auto next = c.intersect({100, 1.5, 7}, {-1, 0, 0}, 1e9);  // facet 1
  ASSERT_TRUE(next);
  EXPECT_TRUE(c.continuous(left->element, next->element));
  const auto far = c.intersect({100, 3.5, 7}, {-1, 0, 0}, 1e9);  // facet 3: too far for one triangle of the atlas
  ASSERT_TRUE(far);
  EXPECT_FALSE(c.continuous(left->element, far->element));
}

TEST(SceneLathe, TheHierarchyFindsWhatEveryTriangleWouldGive) {
  // A bowl (its profile out and back): rays from everywhere, against the
  // nearest of every quad of the surface tried in turn, each built here
  // from the profile.
  const std::vector<glm::dvec2> profile{{0, 0}, {6, 1}, {9, 5}, {10, 9}, {9.5, 9.5}, {8, 4}, {3, 1.5}};
  const int n = 24;
  const glm::dvec3 base(1, 2, 3), normal(0, 1, 0), up(0, 0, 1), right = glm::cross(up, normal);
  const ReceiverMesh bowl = make_lathe(profile, n, base, normal, up);
  const auto at = [&](int i, std::size_t j) {
    const double phi = 2 * std::numbers::pi * i / n;
    return base + profile[j].x * std::sin(phi) * right + profile[j].y * up + profile[j].x * std::cos(phi) * normal;
  };
  // The nearest positive distance to triangle abc, or infinity.
  const auto meet = [](glm::dvec3 o, glm::dvec3 d, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const glm::dvec3 nrm = glm::cross(b - a, c - a);
    const double t = glm::dot(a - o, nrm) / glm::dot(d, nrm);
    const glm::dvec3 p = o + t * d;
    const bool inside = glm::dot(glm::cross(b - a, p - a), nrm) >= 0 && glm::dot(glm::cross(c - b, p - b), nrm) >= 0 &&
                        glm::dot(glm::cross(a - c, p - c), nrm) >= 0;
    return t > 0 && inside ? t : std::numeric_limits<double>::infinity();
  };
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::dvec3 origin = base + glm::dvec3(0, 0, 5) + 20.0 * glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const glm::dvec3 dir = glm::normalize(base + glm::dvec3(6 * g(rng), 6 * g(rng), 5 + 4 * g(rng)) - origin);
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i)
      for (std::size_t j = 0; j + 1 < profile.size(); ++j) {
        nearest = std::min(nearest, meet(origin, dir, at(i, j), at(i + 1, j), at(i, j + 1)));
        nearest = std::min(nearest, meet(origin, dir, at(i + 1, j + 1), at(i, j + 1), at(i + 1, j)));
      }
    const auto found = bowl.intersect(origin, dir, 1e9);
    ASSERT_EQ(found.has_value(), std::isfinite(nearest)) << k;
    if (!found) continue;
    ++hits;
    EXPECT_NEAR(found->distance, nearest, 1e-9) << k;
  }
  EXPECT_GT(hits, 500);  // the rays aim at it: most meet it
}

TEST(SceneLathe, AReceiverReadAgainIsBuiltOnceAndSharedUntilItChanges) {
  // A parameter patch reads its whole scene again, twice: every lathe was
  // built anew each time (seven held the server's main loop 0.3 s a patch).
  json doc = minimal();
  doc["receivers"] = {vase()};
  const Scene first = scene_from_json(doc, ".");
  const Scene again = scene_from_json(doc, ".");
  ASSERT_TRUE(first.receivers[0].lathe && again.receivers[0].lathe);
  EXPECT_EQ(first.receivers[0].lathe->mesh.get(), again.receivers[0].lathe->mesh.get());
  // Moved, or another profile: a mesh of its own, where it now stands.
  doc["receivers"][0]["center"] = {41, 0, -30};
  const Scene moved = scene_from_json(doc, ".");
  EXPECT_NE(moved.receivers[0].lathe->mesh.get(), first.receivers[0].lathe->mesh.get());
  EXPECT_NEAR(moved.receivers[0].lathe->mesh->lower().x - first.receivers[0].lathe->mesh->lower().x, 1.0, 1e-9);
  doc["receivers"][0]["lathe"]["segments"] = 49;
  EXPECT_NE(scene_from_json(doc, ".").receivers[0].lathe->mesh.get(), moved.receivers[0].lathe->mesh.get());
}

TEST(SceneLathe, EveryReceiverAScenesHoldsIsFoundHoweverManyThereAre) {
  // The sessions together may hold more receivers than the few kept for no
  // scene: a patch must still find each rather than build them all again
  // (a cache of the last 32 alone was missed by every patch past that).
  constexpr int kHeld = 48;
  json doc = minimal();
  doc["receivers"] = {vase()};
  std::vector<Scene> held;
  for (int i = 0; i < kHeld; ++i) {
    doc["receivers"][0]["center"] = {40 + i, 0, -30};
    held.push_back(scene_from_json(doc, "."));
  }
  for (int i = 0; i < kHeld; ++i) {
    doc["receivers"][0]["center"] = {40 + i, 0, -30};
    EXPECT_EQ(scene_from_json(doc, ".").receivers[0].lathe->mesh.get(), held[i].receivers[0].lathe->mesh.get())
        << "receiver " << i << " was built again";
  }
  // What no scene holds is let go past the last few: the cache is bounded.
  std::vector<std::weak_ptr<const ReceiverMesh>> dropped;
  for (int i = 0; i < kHeld; ++i) {
    doc["receivers"][0]["center"] = {40 + i, 1, -30};
    dropped.push_back(scene_from_json(doc, ".").receivers[0].lathe->mesh);
  }
  EXPECT_TRUE(dropped.front().expired());
  EXPECT_FALSE(dropped.back().expired());
}
