// SPDX-License-Identifier: LGPL-2.1-or-later
// A session's water over REST: paused water stands still in the stream, a
// drop posted to it shows in the next pictures where the floor lies under
// it; drops are checked and numbered, refused for a scene without water,
// and the pool's grid and size stay the scene's.
#include "caustic/image_io.hpp"
#include "rest_fixture.hpp"

#include <glib.h>

#include <cmath>
#include <cstdio>

using caustic::testing::bearer;
using caustic::testing::expect_problem;
using caustic::testing::http;
using caustic::testing::Response;
using caustic::testing::Rest;
using nlohmann::json;

namespace {

// The session's HDR picture (frame.exr), once it has one.
caustic::HdrImage picture(const std::string& url, const json& s) {
  Response r;
  for (int i = 0; i < 200; ++i) {
    r = http("GET", url + "/frame.exr", "", "", bearer(s));
    if (r.status != 503) break;
    g_usleep(100'000);
  }
  EXPECT_EQ(r.status, 200u) << r.body;
  const std::string file = ::testing::TempDir() + "/water-frame.exr";
  FILE* f = std::fopen(file.c_str(), "wb");
  std::fwrite(r.body.data(), 1, r.body.size(), f);
  std::fclose(f);
  return caustic::read_hdr_image(file);
}

// The mean absolute difference of two pictures over the square of
// half-width `half` pixels about (cx, cy).
double change(const caustic::HdrImage& a, const caustic::HdrImage& b, int cx, int cy, int half) {
  double sum = 0;
  int n = 0;
  for (int y = std::max(0, cy - half); y < std::min(a.height, cy + half); ++y)
    for (int x = std::max(0, cx - half); x < std::min(a.width, cx + half); ++x, ++n) sum += std::abs(a.at(x, y) - b.at(x, y));
  return n ? sum / n : 0.0;
}

}  // namespace

TEST_F(Rest, PausedWaterStandsAndADropShowsUnderIt) {
  const json s = create("pool");
  const std::string url = session_url(s);
  const json water = s["params"]["params"]["water"];
  ASSERT_TRUE(water.is_object()) << s.dump();
  const auto patch = [&](const json& body) {
    return http("PATCH", url + "/params", body.dump(), "application/merge-patch+json", bearer(s));
  };
  ASSERT_EQ(patch({{"water", {{"paused", true}}}}).status, 200u);
  // Frames rendered before the pause took hold may still come: wait for two equal pictures.
  caustic::HdrImage still = picture(url, s), again;
  for (int i = 0; i < 50; ++i) {
    g_usleep(300'000);
    again = picture(url, s);
    if (again.pixels == still.pixels) break;
    still = again;
  }
  ASSERT_EQ(again.pixels, still.pixels) << "paused water kept moving";
  // A deep drop at the pool's centre: the sun (20 degrees off vertical,
  // towards +x) carries its light 0.32 m along x to the floor's centre.
  const Response posted = http("POST", url + "/drops", R"({"x": 0, "y": 0, "strength": 0.03, "radius": 0.08})",
                               "application/json", bearer(s));
  ASSERT_EQ(posted.status, 202u) << posted.body;
  EXPECT_EQ(posted.json()["drop"], 1);
  caustic::HdrImage after;
  for (int i = 0; i < 50; ++i) {
    g_usleep(100'000);
    after = picture(url, s);
    if (after.pixels != still.pixels) break;
  }
  const int cx = after.width / 2, cy = after.height / 2, quarter = after.width / 4;
  const double under = change(still, after, cx, cy, after.width / 16);
  const double corner = change(still, after, cx - quarter - quarter / 2, cy - quarter - quarter / 2, after.width / 16);
  std::printf("paused pool: mean change %.4f under the drop, %.4f in a far corner\n", under, corner);
  EXPECT_GT(under, 0.05);
  EXPECT_LT(corner, 0.1 * under);
  // Still paused: the picture with the drop stands.
  g_usleep(300'000);
  EXPECT_EQ(picture(url, s).pixels, after.pixels);
  // The scene's rain sets what a drop leaves out.
  const Response plain = http("POST", url + "/drops", R"({"x": 0.5, "y": -0.5})", "application/json", bearer(s));
  ASSERT_EQ(plain.status, 202u) << plain.body;
  EXPECT_EQ(plain.json()["drop"], 2);
  EXPECT_EQ(plain.json()["strength"], water["rain_strength"]);
  EXPECT_EQ(plain.json()["radius"], water["drop_radius"]);
}

TEST_F(Rest, BadDropsAreRefusedAndNamed) {
  const json s = create("pool");
  const std::string url = session_url(s) + "/drops";
  const auto post = [&](const std::string& body) { return http("POST", url, body, "application/json", bearer(s)); };
  expect_problem(post(R"({"x": 1.5, "y": 0})"), 422, "x");
  expect_problem(post(R"({"x": 0})"), 422, "y");
  expect_problem(post(R"({"x": "middle", "y": 0})"), 422, "x");
  expect_problem(post(R"({"x": 0, "y": 0, "strength": 1})"), 422, "strength");
  expect_problem(post(R"({"x": 0, "y": 0, "radius": 0.0001})"), 422, "radius");
  expect_problem(post(R"({"x": 0, "y": 0, "splash": true})"), 422, "splash");
  expect_problem(post(R"([0, 0])"), 400);
  expect_problem(post("{"), 400);
  expect_problem(http("POST", url, R"({"x": 0, "y": 0})", "text/plain", bearer(s)), 415);
  expect_problem(http("GET", url, "", "", bearer(s)), 405);
  expect_problem(http("POST", url, R"({"x": 0, "y": 0})", "application/json", {{"Authorization", "Bearer nope"}}), 401);
  // None of them took a number.
  const Response good = post(R"({"x": 0, "y": 0})");
  ASSERT_EQ(good.status, 202u) << good.body;
  EXPECT_EQ(good.json()["drop"], 1);
  // The pool's grid and size are the scene's; so is having water at all.
  const std::string params = session_url(s) + "/params", type = "application/merge-patch+json";
  const json pool_before = http("GET", params, "", "", bearer(s)).json()["params"];
  expect_problem(http("PATCH", params, R"({"water": {"grid": 64}})", type, bearer(s)), 422, "water.grid");
  expect_problem(http("PATCH", params, R"({"water": {"size": 3}})", type, bearer(s)), 422, "water.size");
  expect_problem(http("PATCH", params, R"({"water": {"rain_rate": -1}})", type, bearer(s)), 422, "water.rain_rate");
  EXPECT_EQ(http("GET", params, "", "", bearer(s)).json()["params"], pool_before) << "a refused patch changed the pool";
  const json dry = create("wavy");
  expect_problem(http("POST", session_url(dry) + "/drops", R"({"x": 0, "y": 0})", "application/json", bearer(dry)), 409);
  // Water belongs to a surface, and the slab is none: refused naming the key written.
  const json dry_before = http("GET", session_url(dry) + "/params", "", "", bearer(dry)).json()["params"];
  expect_problem(http("PATCH", session_url(dry) + "/params", R"({"water": {}})", type, bearer(dry)), 422, "water");
  EXPECT_EQ(http("GET", session_url(dry) + "/params", "", "", bearer(dry)).json()["params"], dry_before);
  const Response metrics = http("GET", server_.url() + "/metrics");
  EXPECT_NE(metrics.body.find("causticd_water_drops_total 1\n"), std::string::npos);
}
