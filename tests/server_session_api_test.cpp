// SPDX-License-Identifier: LGPL-2.1-or-later
// The session endpoints beyond the parameters: the picture a REST client
// sees without WebRTC (frame.png, frame.exr), a null that resets to the
// scene's own value, and parse errors that say where the body broke.
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

// What a client without WebRTC sees: the picture and the HDR image that the
// session renders, each at the stream's size, changing with a PATCH.
TEST_F(Rest, FramePngAndExrShowWhatTheSessionRenders) {
  const json s = create("lens");
  const std::string dir = ::testing::TempDir();
  auto fetch = [&](const std::string& name, const std::string& type) {
    Response r;
    // The first picture takes a moment to render; 503 with Retry-After until then.
    for (int i = 0; i < 100; ++i) {
      r = http("GET", session_url(s) + "/" + name, "", "", bearer(s));
      if (r.status != 503) break;
      g_usleep(100'000);
    }
    EXPECT_EQ(r.status, 200u) << r.body;
    EXPECT_EQ(r.content_type, type);
    const std::string file = dir + "/" + name;
    FILE* f = std::fopen(file.c_str(), "wb");
    std::fwrite(r.body.data(), 1, r.body.size(), f);
    std::fclose(f);
    return caustic::read_hdr_image(file);
  };
  const caustic::HdrImage png = fetch("frame.png", "image/png");
  const caustic::HdrImage exr = fetch("frame.exr", "image/x-exr");
  ASSERT_EQ(png.width, exr.width);
  ASSERT_EQ(png.height, exr.height);
  EXPECT_GE(png.width, 16);
  // The lens focuses: the HDR peak is many times the light's irradiance and
  // lands bright in the picture; a corner of the screen stays dark.
  std::size_t peak = 0;
  for (std::size_t i = 0; i < exr.pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(exr.pixels[i]) && exr.pixels[i] >= 0) << i;
    if (exr.pixels[i] > exr.pixels[peak]) peak = i;
  }
  EXPECT_GT(exr.pixels[peak], 10.0f);
  EXPECT_GT(png.pixels[peak], 0.8f);
  EXPECT_LT(png.at(0, 0), 0.05f);
  // A darker manual exposure shows in the next picture.
  // (An exposure that maps the peak to 1 - exp(-0.01), grey 31 of 255.)
  const json dark = {{"post", {{"exposure_mode", "manual"}, {"exposure", 0.01 / exr.pixels[peak]}}}};
  ASSERT_EQ(http("PATCH", session_url(s) + "/params", dark.dump(), "application/merge-patch+json", bearer(s)).status,
            200u);
  float after = 1;
  for (int i = 0; i < 50 && after > 0.5f; ++i, g_usleep(100'000)) after = fetch("frame.png", "image/png").pixels[peak];
  EXPECT_LT(after, 0.5f);
  // Only the holder of the session's token sees it; only GET and HEAD.
  expect_problem(http("GET", session_url(s) + "/frame.png", "", "", {{"Authorization", "Bearer nope"}}), 401);
  expect_problem(http("POST", session_url(s) + "/frame.png", "", "", bearer(s)), 405);
}

// A null resets to the scene's own value; a body that is not JSON is told
// where it broke.
TEST_F(Rest, NullRestoresTheScenesValueAndParseErrorsSayWhere) {
  const json s = create("wavy");
  const std::string url = session_url(s) + "/params";
  const json scene_post = s["params"]["params"]["post"];
  const std::string type = "application/merge-patch+json";
  ASSERT_EQ(http("PATCH", url, R"({"post": {"bloom_radius": 1, "gamma": 1.0}})", type, bearer(s)).status, 200u);
  const Response one = http("PATCH", url, R"({"post": {"bloom_radius": null}})", type, bearer(s));
  ASSERT_EQ(one.status, 200u) << one.body;
  EXPECT_EQ(one.json()["params"]["post"]["bloom_radius"], scene_post["bloom_radius"]);
  EXPECT_EQ(one.json()["params"]["post"]["gamma"], 1.0);
  const Response all = http("PATCH", url, R"({"post": null})", type, bearer(s));
  EXPECT_EQ(all.json()["params"]["post"], scene_post);
  const Response broken = http("PATCH", url, "{\n  \"post\": {\n  }\n  ,}", type, bearer(s));
  expect_problem(broken, 400);
  EXPECT_NE(broken.json().value("detail", "").find("at line 4, column 4"), std::string::npos) << broken.body;
}


// The built-in scenes follow the light: a turned light takes the screen
// rectangle with it (by the plane distance times the tangent, measured from
// the public proxy's flat face), and a centre written meanwhile is named.
TEST_F(Rest, TheScreenFollowsATurnedLight) {
  const json s = create("lens");
  const std::string url = session_url(s) + "/params";
  const std::string type = "application/merge-patch+json";
  const json start = s["params"]["params"]["screen"];
  ASSERT_EQ(start["follow_light"], true);
  const json proxy = http("GET", server_.url() + "/api/v1/scenes/lens").json()["proxy"];
  const double flat_z = proxy["center"][2].get<double>() + 0.5 * proxy["thickness"].get<double>();
  const double d = flat_z - start["center"][2].get<double>();
  EXPECT_NEAR(start["center"][0].get<double>(), proxy["center"][0].get<double>(), 1e-9) << "straight down: under the lens";
  const double t = std::tan(34 * M_PI / 180);
  const Response turned = http("PATCH", url, json{{"light", {{"direction", {t, 0, -1}}}}}.dump(), type, bearer(s));
  ASSERT_EQ(turned.status, 200u) << turned.body;
  const json screen = turned.json()["params"]["screen"];
  EXPECT_NEAR(screen["center"][0].get<double>() - proxy["center"][0].get<double>(), d * t, 1e-6);
  EXPECT_NEAR(screen["center"][2].get<double>(), start["center"][2].get<double>(), 1e-9) << "the plane stays";
  EXPECT_TRUE(turned.json()["warnings"].empty()) << turned.body;

  const Response placed = http("PATCH", url, R"({"screen": {"center": [5, 5, -70]}})", type, bearer(s));
  ASSERT_EQ(placed.status, 200u) << placed.body;
  ASSERT_EQ(placed.json()["warnings"].size(), 1u) << placed.body;
  EXPECT_EQ(placed.json()["warnings"][0]["key"], "screen.center");
  EXPECT_NEAR(placed.json()["params"]["screen"]["center"][2].get<double>(), -70, 1e-9) << "its plane is used";
  const Response fixed =
      http("PATCH", url, R"({"screen": {"follow_light": false, "center": [5, 5, -70]}})", type, bearer(s));
  EXPECT_EQ(fixed.json()["params"]["screen"]["center"], json({5.0, 5.0, -70.0})) << fixed.body;
  EXPECT_EQ(fixed.json()["warnings"].size(), 1u) << "the light now misses most of the screen: " << fixed.body;

  // A key its own section leaves unused is said too, and still stored.
  const Response unused = http("PATCH", url, R"({"post": {"exposure_mode": "manual", "auto_percentile": 0.9}})", type,
                               bearer(s));
  ASSERT_EQ(unused.status, 200u) << unused.body;
  const json answer = unused.json();
  bool said = false;
  for (const auto& w : answer["warnings"]) said = said || w["key"] == "post.auto_percentile";
  EXPECT_TRUE(said) << unused.body;
  EXPECT_EQ(answer["params"]["post"]["auto_percentile"], 0.9);
}
