// SPDX-License-Identifier: LGPL-2.1-or-later
// The session endpoints beyond the parameters: the picture a REST client
// sees without WebRTC (frame.png, frame.exr), a null that resets to the
// scene's own value, and parse errors that say where the body broke.
#include "caustic/image_io.hpp"
#include "raw_http.hpp"
#include "rest_fixture.hpp"

#include <glib.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>

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

namespace {

// The server's peak resident memory so far (VmHWM), in MB.
double peak_mb(const std::string& pid) {
  std::ifstream status("/proc/" + pid + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

}  // namespace

// Requests for the picture made together share one copy and one encoding,
// made on the session's render thread: forty at once once held forty
// copies of a colour picture (20 MB each at 1024²) and encoded each on the
// main loop. At most 16 wait; beyond, 429. Bounded: 40 requests, 15 s each.
TEST_F(Rest, FrameRequestsMadeTogetherShareOnePicture) {
  const json s = create("lens");
  const json colour = {{"object", {{"glass", "bk7"}}}};
  const Response patched = http("PATCH", session_url(s) + "/params", colour.dump(), "application/merge-patch+json", bearer(s));
  ASSERT_EQ(patched.status, 200u) << patched.body;
  for (int i = 0; i < 100 && http("GET", session_url(s) + "/frame.exr", "", "", bearer(s)).status != 200; ++i)
    g_usleep(100'000);
  // Past the picture left standing (drawn again half a second after the
  // change) and the last answer's reuse: the burst asks for one of its own.
  g_usleep(1'500'000);
  const double before = peak_mb(server_.pid());
  const std::string request =
      caustic::testing::request_text("GET", s["url"].get<std::string>() + "/frame.exr",
                                     "Authorization: Bearer " + s["token"].get<std::string>() + "\r\n");
  std::vector<int> sockets;
  for (int i = 0; i < 40; ++i) {
    const int fd = caustic::testing::raw_connect(server_.port());
    ASSERT_GE(fd, 0);
    caustic::testing::raw_send(fd, request);
    sockets.push_back(fd);
  }
  int pictures = 0;
  std::set<std::string> bodies;
  for (const int fd : sockets) {
    const std::string answer = caustic::testing::raw_read_all(fd, 15000);
    ::close(fd);
    const int status = caustic::testing::raw_status(answer);
    if (status == 429) {
      EXPECT_EQ(caustic::testing::raw_header(answer, "Retry-After"), "1");
      EXPECT_NE(answer.find("wait for this session's next picture"), std::string::npos) << answer.substr(0, 400);
      continue;
    }
    ASSERT_EQ(status, 200) << answer.substr(0, 400);
    ++pictures;
    bodies.insert(caustic::testing::raw_body(answer));
  }
  EXPECT_GE(pictures, 16);
  // One encoding for those that waited together (a busy machine may read
  // the forty in a few turns of the render thread).
  EXPECT_LE(bodies.size(), 3u);
  // One copy and one EXR (12 MB of floats, 20 MB with the rest): far from forty.
  EXPECT_LT(peak_mb(server_.pid()) - before, 200.0) << "peak memory grew by " << peak_mb(server_.pid()) - before << " MB";
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
  EXPECT_EQ(http("GET", url, "", "", bearer(s)).json()["params"]["post"], scene_post) << "the refused body changed it";
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
