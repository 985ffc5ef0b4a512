// SPDX-License-Identifier: LGPL-2.1-or-later
// Visitors' pictures over the API (POST /api/v1/designs): a picture becomes
// a streamable scene whose caustic is the picture; bad uploads are refused
// with problem+json and leave nothing behind; limits, tokens, restarts and
// expiry. Black box against `causticd serve` on loopback; every wait bounded.
#include "design_api_support.hpp"
#include "jpeg_support.hpp"
#include "openapi_check.hpp"
#include "png_chunk.hpp"

#include <sys/stat.h>

#include <ctime>
#include <fstream>
#include <limits>

using namespace caustic::testing::design_api;

// Built without the designer, the API says so and nothing else changes.
TEST(DesignApiOff, WithoutTheDesignerUploadsAnswer501) {
  if (DESIGN_BUILT_IN) GTEST_SKIP() << "the designer is built in";
  ServerProcess server;
  expect_problem(upload(server, square_png()), 501, "not built");
}

TEST_F(DesignApi, APictureBecomesAPrivateSceneWhoseCausticIsThePicture) {
  TempDir state;
  ServerProcess server(small_designs(state));
  const Response posted = upload(server, square_png(), "image/png", "?name=Square");
  ASSERT_EQ(posted.status, 202u) << posted.body;
  const json ticket = posted.json();
  const std::string id = ticket["id"];
  EXPECT_EQ(ticket["status_url"], "/api/v1/designs/" + id);
  const caustic::testing::OpenApi api;
  EXPECT_EQ(api.check("/api/v1/designs", "post", 202, posted.content_type, ticket), "");
  const json done = wait_design(server, id);
  ASSERT_EQ(done.value("state", ""), "ready") << done.dump();
  EXPECT_EQ(api.check("/api/v1/designs/{id}", "get", 200, "application/json", done), "");
  EXPECT_EQ(done["name"], "Square");
  EXPECT_EQ(done["scene"], id);
  EXPECT_EQ(done["report"]["tir_vertices"], 0);
  EXPECT_EQ(done["report"]["warnings"], json::array());
  // A ready design converged: at most 5% of the light misplaced, and some
  // residual is always left (the solve stops at a stall, not at zero).
  EXPECT_GT(done["report"]["transport_residual"].get<double>(), 0.0) << done.dump();
  EXPECT_LE(done["report"]["transport_residual"].get<double>(), 0.05) << done.dump();
  EXPECT_GT(done["report"]["engine"]["ssim"].get<double>(), 0.9) << done.dump();
  // The face's own figures describe the hidden mesh: never in the answer.
  for (const char* secret : {"relief_mm", "max_slope_deg", "min_thickness_mm"})
    EXPECT_EQ(done.dump().find(secret), std::string::npos) << secret;

  // The thumbnail is the engine's render: the light lands in the square.
  // Its tone map (v = (1 - exp(-e E))^(1/2.2)) is undone to compare
  // irradiance; the target's contrast is 10:1, bloom spills a little.
  const Response thumb = http("GET", server.url() + "/api/v1/scenes/" + id + "/thumbnail.png");
  ASSERT_EQ(thumb.status, 200u);
  const fs::path png = state.path / "thumb.png";
  std::ofstream(png, std::ios::binary) << thumb.body;
  const caustic::HdrImage render = caustic::read_hdr_image(png);
  double inside = 0, outside = 0;
  int n_in = 0, n_out = 0;
  for (int y = 0; y < render.height; ++y)
    for (int x = 0; x < render.width; ++x) {
      const double v = -std::log(1.0 - std::min(0.999, std::pow(render.pixels[std::size_t(y) * render.width + x], 2.2)));
      const double dx = std::abs(x + 0.5 - render.width / 2.0) / render.width;
      const double dy = std::abs(y + 0.5 - render.height / 2.0) / render.height;
      if (dx < 0.2 && dy < 0.2) {
        inside += v;
        ++n_in;
      } else if (dx > 0.3 || dy > 0.3) {
        outside += v;
        ++n_out;
      }
    }
  EXPECT_GT(inside / n_in, 5 * (outside / n_out)) << inside / n_in << " vs " << outside / n_out;

  // A new session streams it; the public list does not show it.
  const Response session = http("POST", server.url() + "/api/v1/sessions", json{{"scene", id}}.dump());
  EXPECT_EQ(session.status, 201u) << session.body;
  EXPECT_EQ(http("GET", server.url() + "/api/v1/scenes").body.find(id), std::string::npos);
  const json one = http("GET", server.url() + "/api/v1/scenes/" + id).json();
  EXPECT_EQ(api.check("/api/v1/scenes/{id}", "get", 200, "application/json", one), "");
  EXPECT_EQ(one["kind"], "designed");
  EXPECT_TRUE(one["proxy"].is_object());
  // The picture itself is not kept once designed.
  for (const auto& f : fs::directory_iterator(state.path / "designs" / id))
    EXPECT_NE(f.path().stem(), "picture") << f.path();
}

// An animated PNG looks like one picture to whoever sends it (a browser
// plays it); only its still image is designed, and the report says so.
TEST_F(DesignApi, AnAnimatedPictureIsDesignedFromItsFirstImageAndSaidSo) {
  TempDir state;
  ServerProcess server(small_designs(state));
  const Response posted = upload(server, caustic::testing::animated_png(square_png(), 3));
  ASSERT_EQ(posted.status, 202u) << posted.body;
  const json done = wait_design(server, posted.json()["id"]);
  ASSERT_EQ(done.value("state", ""), "ready") << done.dump();
  EXPECT_EQ(caustic::testing::OpenApi().check("/api/v1/designs/{id}", "get", 200, "application/json", done), "");
  EXPECT_EQ(done["report"]["warnings"],
            json::parse(R"([{"key": "picture", "detail": "holds 3 images (pages, frames or parts); only the first is designed"}])"))
      << done.dump();
  EXPECT_EQ(done.dump().find(state.path.string()), std::string::npos) << done.dump();
}

TEST_F(DesignApi, AColourPictureDesignedInColourThrowsItsColours) {
  // Left half red, right half green: the tinted face must throw red light
  // on the left and green on the right (docs/design.md "Colour").
  const int n = 128;
  caustic::Rgba8Image image{n, n, std::vector<std::uint8_t>(std::size_t(n) * n * 4, 255)};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::uint8_t red[3] = {250, 40, 20}, green[3] = {30, 240, 60};
      for (int c = 0; c < 3; ++c) image.pixels[(std::size_t(y) * n + x) * 4 + c] = x < n / 2 ? red[c] : green[c];
    }
  const auto bytes = caustic::encode_png(image);
  TempDir state;
  ServerProcess server(small_designs(state));
  const Response posted = upload(server, std::string(bytes.begin(), bytes.end()), "image/png", "?colour=true");
  ASSERT_EQ(posted.status, 202u) << posted.body;
  const std::string id = posted.json()["id"];
  const json done = wait_design(server, id);
  ASSERT_EQ(done.value("state", ""), "ready") << done.dump();
  EXPECT_EQ(done["colour"], true);
  EXPECT_EQ(caustic::testing::OpenApi().check("/api/v1/designs/{id}", "get", 200, "application/json", done), "");
  EXPECT_LT(done["report"]["engine"]["chromaticity_error"].get<double>(), 0.02) << done.dump();
  ASSERT_EQ(done["report"]["engine"]["relative_l1_rgb"].size(), 3u) << done.dump();

  const Response thumb = http("GET", server.url() + "/api/v1/scenes/" + id + "/thumbnail.png");
  ASSERT_EQ(thumb.status, 200u);
  const fs::path png = state.path / "thumb.png";
  std::ofstream(png, std::ios::binary) << thumb.body;
  const caustic::RgbHdrImage render = caustic::read_rgb_image(png);
  double left[3] = {0, 0, 0}, right[3] = {0, 0, 0};
  for (int y = render.height / 4; y < 3 * render.height / 4; ++y)
    for (int x = 0; x < render.width; ++x) {
      const double u = (x + 0.5) / render.width;
      if (std::abs(u - 0.5) < 0.1 || u < 0.1 || u > 0.9) continue;
      for (int c = 0; c < 3; ++c) (u < 0.5 ? left : right)[c] += render.pixels[3 * (std::size_t(y) * render.width + x) + c];
    }
  EXPECT_GT(left[0], 2 * left[1]) << "the left is red";
  EXPECT_GT(right[1], 2 * right[0]) << "the right is green";

  // Restarted, the design keeps its colour.
  server.stop();
  ServerProcess again(small_designs(state));
  const json restored = wait_design(again, id);
  EXPECT_EQ(restored.value("state", ""), "ready") << restored.dump();
  EXPECT_EQ(restored["colour"], true);
}

TEST_F(DesignApi, BadUploadsAreRefusedAndLeaveNothingBehind) {
  TempDir state;
  auto args = small_designs(state);
  for (const char* kv : {"design_max_upload_bytes=100000", "design_max_pixels=1000000"})
    args.insert(args.end(), {"--set", kv});
  ServerProcess server(args);
  expect_problem(upload(server, "hello", "text/plain"), 415, "image/png or image/jpeg");
  expect_problem(upload(server, "hello", "image/png"), 415, "not image/png");
  expect_problem(upload(server, square_png(), "image/jpeg"), 415, "not image/jpeg");
  expect_problem(upload(server, std::string(1, '\0'), "image/png"), 415);
  // A PNG header that claims 20000 x 20000 pixels: refused from the header.
  std::string huge = square_png().substr(0, 33);
  for (int i = 0; i < 2; ++i) {
    const unsigned v = 20000;
    for (int b = 0; b < 4; ++b) huge[16 + 4 * i + b] = static_cast<char>((v >> (24 - 8 * b)) & 0xff);
  }
  expect_problem(upload(server, huge, "image/png"), 413, "20000x20000");
  // 20000 x 1 is few pixels but a side beyond the designer's: refused as well, not queued to fail.
  std::string wide = square_png();
  for (int i = 0; i < 2; ++i) {
    const unsigned v = i == 0 ? 20000 : 1;
    for (int b = 0; b < 4; ++b) wide[16 + 4 * i + b] = static_cast<char>((v >> (24 - 8 * b)) & 0xff);
  }
  expect_problem(upload(server, wide, "image/png"), 413, "a side");
  // Cut short: its header is whole, its end is missing.
  expect_problem(upload(server, square_png().substr(0, square_png().size() / 2), "image/png"), 415, "ends before");
  expect_problem(upload(server, square_png().substr(0, 20), "image/png"), 422, "broken");
  // A progressive JPEG whose last scan comes a hundred times more: each scan
  // is decoded anew (140,000 held a worker and the queue behind it for 40 min).
  const std::string bomb = caustic::testing::with_last_scan_repeated(caustic::testing::jpeg_bytes(64, 64, true), 100);
  expect_problem(upload(server, bomb, "image/jpeg"), 422, "scans");
  // Asking first, as a client sending a large body should: the server's
  // early 413 then never races the body into a closed connection.
  expect_problem(upload(server, std::string(100001, 'x'), "image/png", "", {{"Expect", "100-continue"}}), 413,
                 "100000 bytes");
  expect_problem(upload(server, square_png(), "image/png", "?name=%01"), 422, "control");
  for (const char* name : {"%C2%85x", "%E2%80%A8", "a%E2%80%AEb"})  // NEL, a line separator, a right-to-left override
    expect_problem(upload(server, square_png(), "image/png", std::string("?name=") + name), 422, "control");
  expect_problem(upload(server, square_png(), "image/png", "?name=" + std::string(65, 'a')), 422, "name");
  expect_problem(upload(server, square_png(), "image/png", "?shape=round"), 422, "shape: unknown query key");
  expect_problem(upload(server, square_png(), "image/png", "?name=a&name=b"), 422, "name is given twice");
  expect_problem(upload(server, square_png(), "image/png", "?colour=true&colour=false"), 422, "colour is given twice");
  expect_problem(upload(server, square_png(), "image/png", "?name"), 422, "name needs a value");
  expect_problem(upload(server, square_png(), "image/png", "?colour=red"), 422, "colour must be");
  const Response list = http("GET", server.url() + "/api/v1/designs");
  expect_problem(list, 405);
  expect_problem(http("GET", server.url() + "/api/v1/designs/0123456789abcdef0123456789abcdef"), 404);
  EXPECT_EQ(folders_in(state.path / "designs"), 0);

  // Pictures that decode to nothing usable fail as jobs, saying why and
  // naming no file of the server.
  // (Its middle cut out: the end is whole, the image data is not.)
  const std::string whole = square_png();
  const std::string cut = whole.substr(0, whole.size() / 2) + whole.substr(whole.size() - 12);
  const std::string black = square_png(128, 0);
  for (const std::string& body : {cut, black}) {
    const Response posted = upload(server, body);
    ASSERT_EQ(posted.status, 202u) << posted.body;
    const json done = wait_design(server, posted.json()["id"]);
    EXPECT_EQ(done.value("state", ""), "failed") << done.dump();
    const std::string error = done.value("error", "");
    EXPECT_FALSE(error.empty());
    // Kept an hour for its uploader to read, not a week among the stored designs.
    EXPECT_LE(done.value("expires", std::int64_t{0}) - static_cast<std::int64_t>(std::time(nullptr)), 3600) << done.dump();
    EXPECT_EQ(error.find('/'), std::string::npos) << error;
    EXPECT_EQ(error.find(state.path.string()), std::string::npos) << error;
  }
  EXPECT_NE(wait_design(server, upload(server, black).json()["id"]).value("error", "").find("all black"),
            std::string::npos);
}

TEST_F(DesignApi, TheQueueIsBoundedAndUploadsAreRateLimited) {
  TempDir state;
  // A 512^2 design takes seconds; two uploads sent at once meet a full queue.
  ServerProcess server({"--set", "state_dir=" + state.path.string(), "--set", "design_queue=1", "--set",
                        "design_uploads_per_hour=2"});
  const Response first = upload(server, square_png(512));
  ASSERT_EQ(first.status, 202u) << first.body;
  expect_problem(upload(server, square_png(512)), 503, "queue is full");
  // The refused upload designed nothing and spent nothing of the hour's
  // two (it once did): once the queue is free, the second goes in...
  wait_design(server, first.json()["id"]);
  EXPECT_EQ(upload(server, square_png(128)).status, 202u);
  // ...and the third is beyond the address's hourly allowance.
  expect_problem(upload(server, square_png(128)), 429, "an hour");
}

TEST_F(DesignApi, UploadsCanBeTurnedOffOrNeedAToken) {
  {
    ServerProcess server({"--set", "design_uploads=off"});
    expect_problem(upload(server, square_png()), 403, "turned off");
  }
  TempDir state;
  auto args = small_designs(state);
  args.insert(args.end(), {"--set", "design_upload_token=uploads-secret-0123456789"});
  ServerProcess server(args);
  expect_problem(upload(server, square_png()), 401, "bearer token");
  expect_problem(upload(server, square_png(), "image/png", "", {{"Authorization", "Bearer wrong-token-0123456789"}}),
                 401);
  EXPECT_EQ(upload(server, square_png(), "image/png", "", {{"Authorization", "Bearer uploads-secret-0123456789"}}).status,
            202u);
}

TEST_F(DesignApi, OnlyAFewScenesStayInMemoryAndTheStoreIsBounded) {
  TempDir state;
  auto args = small_designs(state);
  args.insert(args.end(), {"--set", "design_max_stored=6", "--set", "max_sessions=8"});
  ServerProcess server(args);
  std::vector<std::string> ids;
  for (int i = 0; i < 6; ++i) {
    const Response posted = upload(server, square_png());
    ASSERT_EQ(posted.status, 202u) << posted.body;
    ids.push_back(posted.json()["id"]);
    ASSERT_EQ(wait_design(server, ids.back()).value("state", ""), "ready");
  }
  // The seventh would exceed what the server keeps.
  expect_problem(upload(server, square_png()), 503, "at most 6");
  // The first design has left memory (four are kept): its scene is read
  // back on demand, the answer meanwhile says to retry.
  expect_problem(http("POST", server.url() + "/api/v1/sessions", json{{"scene", ids.front()}}.dump()), 503,
                 "being loaded");
  const Response session = create_session_retrying(server, ids.front());
  EXPECT_EQ(session.status, 201u) << session.body;
  // Its description and thumbnail never needed the scene.
  EXPECT_EQ(http("GET", server.url() + "/api/v1/scenes/" + ids[1]).status, 200u);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/scenes/" + ids[1] + "/thumbnail.png").status, 200u);
}
