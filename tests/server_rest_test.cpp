// SPDX-License-Identifier: LGPL-2.1-or-later
// The REST API of `causticd serve`, black-box over loopback: every endpoint,
// every documented error, and the parameters unchanged after each error.
#include "openapi_check.hpp"
#include "rest_fixture.hpp"
#include "server_process.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

using caustic::testing::expect_problem;
using caustic::testing::bearer;
using caustic::testing::http;
using caustic::testing::Response;
using caustic::testing::Rest;
using caustic::testing::ServerProcess;
using nlohmann::json;

namespace {


}  // namespace

TEST_F(Rest, HealthSaysLittleToAnyone) {
  const Response r = http("GET", server_.url() + "/api/v1/health");
  ASSERT_EQ(r.status, 200u);
  const json h = r.json();
  EXPECT_EQ(h["status"], "ok");
  EXPECT_EQ(h["sessions"], 0);
  // The renderer (GPU model, driver) is for the operator's log, not for visitors.
  EXPECT_FALSE(h.contains("renderer"));
  EXPECT_EQ(r.body.find("llvmpipe"), std::string::npos);
  EXPECT_TRUE(h["version"].is_string());
  expect_problem(http("DELETE", server_.url() + "/api/v1/health"), 405);
  expect_problem(http("GET", server_.url() + "/api/v1/nothing"), 404);
}

TEST_F(Rest, GalleryListsScenesWithThumbnailsAndNeverTheMesh) {
  const Response r = http("GET", server_.url() + "/api/v1/scenes");
  ASSERT_EQ(r.status, 200u);
  EXPECT_EQ(r.body.find(".obj"), std::string::npos) << "a mesh path leaked";
  EXPECT_EQ(r.body.find("\"mesh\""), std::string::npos);
  std::set<std::string> ids;
  const json listing = r.json();
  for (const auto& s : listing["scenes"]) {
    ids.insert(s["id"]);
    EXPECT_FALSE(s["name"].get<std::string>().empty());
    EXPECT_EQ(s["proxy"]["outline"].size(), 2u);
    EXPECT_GT(s["proxy"]["thickness"].get<double>(), 0.0);
    const Response png = http("GET", server_.url() + s["thumbnail"].get<std::string>());
    EXPECT_EQ(png.status, 200u);
    EXPECT_EQ(png.content_type, "image/png");
    EXPECT_EQ(png.body.substr(1, 3), "PNG");
  }
  // The optics classics, and the designed objects that the build always
  // makes (the photographs need their Debian package); designed ones first.
  for (const char* id : {"cylinder", "lens", "prism", "slab", "wavy"}) EXPECT_TRUE(ids.count(id)) << id;
  // The glasses object.glass may name, for the viewer's panel.
  const auto& glasses = listing["glasses"];
  ASSERT_TRUE(glasses.is_array());
  for (const char* name : {"bk7", "fused_silica", "pmma", "polycarbonate", "water"})
    EXPECT_NE(std::find(glasses.begin(), glasses.end(), name), glasses.end()) << name;
  if (DESIGN_BUILT_IN) {
    for (const char* id : {"design-logo", "design-text"}) EXPECT_TRUE(ids.count(id)) << id;
  }
  bool classics_began = false;
  for (const auto& s : listing["scenes"]) {
    const std::string id = s["id"];
    const bool designed = id.rfind("design-", 0) == 0;
    EXPECT_EQ(s["kind"], designed ? "designed" : "classic") << id;
    EXPECT_FALSE(designed && classics_began) << id << " comes after a classic";
    classics_began = classics_began || !designed;
  }
  expect_problem(http("GET", server_.url() + "/api/v1/scenes/nope/thumbnail.png"), 404);
}

TEST_F(Rest, SessionLifecycle) {
  const json s = create();
  ASSERT_TRUE(s["id"].is_string());
  EXPECT_EQ(s["token"].get<std::string>().size(), 32u);
  EXPECT_EQ(s["signal_url"], "/api/v1/sessions/" + s["id"].get<std::string>() + "/signal?token=" +
                                 s["token"].get<std::string>());
  EXPECT_EQ(s["params"]["version"], 1);
  EXPECT_FALSE(s["params"]["params"].contains("mesh"));

  const Response got = http("GET", session_url(s) + "/params", "", "", bearer(s));
  ASSERT_EQ(got.status, 200u);
  EXPECT_EQ(got.json(), s["params"]);

  const Response patched = http("PATCH", session_url(s) + "/params", R"({"object": {"ior": 1.7}})",
                                "application/merge-patch+json", bearer(s));
  ASSERT_EQ(patched.status, 200u) << patched.body;
  EXPECT_EQ(patched.json()["version"], 2);
  EXPECT_DOUBLE_EQ(patched.json()["params"]["object"]["ior"].get<double>(), 1.7);
  EXPECT_EQ(patched.json()["atlas"].size(), 1u);  // the screen, the whole picture
  EXPECT_EQ(http("GET", server_.url() + "/api/v1/health").json()["sessions"], 1);
  // A floor under the screen: the picture becomes two tiles, side by side.
  const Response floor = http("PATCH", session_url(s) + "/params",
                              R"({"receivers": [{"center": [0, 0, -120], "width": 60, "height": 60}]})",
                              "application/merge-patch+json", bearer(s));
  ASSERT_EQ(floor.status, 200u) << floor.body;
  const json atlas = floor.json()["atlas"];
  const json width = floor.json()["params"]["render"]["width"];
  ASSERT_EQ(atlas.size(), 2u);
  EXPECT_EQ(atlas[1]["x"], width.get<int>() / 2);
  EXPECT_EQ(atlas[1]["width"], width.get<int>() / 2);

  expect_problem(http("DELETE", session_url(s), "", "", {{"Authorization", "Bearer nope"}}), 401);
  EXPECT_EQ(http("DELETE", session_url(s), "", "", bearer(s)).status, 204u);
  // An ended session and a wrong token look alike: 401.
  expect_problem(http("GET", session_url(s) + "/params", "", "", bearer(s)), 401);
  EXPECT_EQ(http("GET", server_.url() + "/api/v1/health").json()["sessions"], 0);
}

TEST_F(Rest, CreateRejectsBadRequests) {
  const std::string url = server_.url() + "/api/v1/sessions";
  expect_problem(http("POST", url, "{\"scene\": ", "application/json"), 400);
  expect_problem(http("POST", url, "[1, 2]", "application/json"), 400);
  expect_problem(http("POST", url, R"({"scene": "lens"})", "text/plain"), 415);
  expect_problem(http("POST", url, R"({"scene": "lens", "colour": 1})"), 422, "colour");
  expect_problem(http("POST", url, R"({"codec": "vp8"})"), 422, "scene");
  expect_problem(http("POST", url, R"({"scene": 5})"), 422, "scene");
  expect_problem(http("POST", url, R"({"scene": "../lens"})"), 422, "scene");
  expect_problem(http("POST", url, R"({"scene": "lens", "codec": "av1"})"), 422, "codec");
  expect_problem(http("POST", url, "{\"scene\": \"" + std::string(100000, 'x') + "\"}"), 413);
  EXPECT_EQ(http("GET", server_.url() + "/api/v1/health").json()["sessions"], 0);
}

TEST_F(Rest, PatchErrorsLeaveTheParametersUnchanged) {
  const json s = create("wavy");
  const std::string url = session_url(s) + "/params";
  const json before = http("GET", url, "", "", bearer(s)).json();
  const std::string patch_type = "application/merge-patch+json";
  struct Case {
    std::string body, type;
    std::vector<std::pair<std::string, std::string>> headers;
    guint status;
    std::string key;
  };
  const std::vector<Case> cases = {
      {"{\"object\": ", patch_type, bearer(s), 400, ""},
      {"NaN", patch_type, bearer(s), 400, ""},
      {R"({"object": {"ior": NaN}})", patch_type, bearer(s), 400, ""},
      {R"({"object": {"ior": 1e999}})", patch_type, bearer(s), 400, ""},
      {R"([1])", patch_type, bearer(s), 400, ""},
      {R"({"object": {"ior": 1.7, "ior": 1.4}})", patch_type, bearer(s), 400, ""},  // which one? neither
      {R"({"object": {"ior": "glass"}})", patch_type, bearer(s), 422, "object.ior"},
      {R"({"object": {"ior": 0.2}})", patch_type, bearer(s), 422, "object.ior"},
      {R"({"light": {"direction": [0, 0, 0]}})", patch_type, bearer(s), 422, "light.direction"},
      {R"({"light": {"kind": "sun"}})", patch_type, bearer(s), 422, "light.kind"},
      {R"({"post": {"gamma": -1}})", patch_type, bearer(s), 422, "post.gamma"},
      {R"({"screen": {"center": [0, 0, 1]}})", patch_type, bearer(s), 422, "screen.center"},
      {R"({"mesh": "/etc/passwd"})", patch_type, bearer(s), 422, "mesh"},
      {R"({"render": {"width": 64}})", patch_type, bearer(s), 422, "render.width"},
      {R"({"object": {"shape": "solid"}})", patch_type, bearer(s), 422, "object.shape"},
      {R"({"render": {"light_grid": 4}})", patch_type, bearer(s), 422, "render.light_grid"},
      {R"({"receivers": [{"width": 0}]})", patch_type, bearer(s), 422, "receivers[0].width"},
      {R"({"receivers": [{"center": [0, 0, 1]}]})", patch_type, bearer(s), 422, "receivers[0].center"},  // through the slab
      {R"({"receivers": [{"lathe": {"profile": [[0, 0], [0, 5]]}}]})", patch_type, bearer(s), 422,
       "receivers[0].lathe.profile"},
      {R"({"receivers": [{"center": [0, 0, -5], "normal": [1, 0, 0], "up": [0, 0, 1], "lathe": {"profile": [[3, 0], [3, 9]]}}]})",
       patch_type, bearer(s), 422,
       "receivers[0].lathe"},  // reaching up into the slab
      {R"({"receivers": [{"center": [0, 0, -40], "mesh": "cloth"}]})", patch_type, bearer(s), 422,
       "receivers[0].mesh"},  // this scene brings no shapes
      {R"({"receiver_meshes": {"x": "/etc/passwd"}})", patch_type, bearer(s), 422, "receiver_meshes"},
      {R"({"render": {"fidelity": "best"}})", patch_type, bearer(s), 422, "render.fidelity"},
      {R"({"render": {"accuracy_target": 0}})", patch_type, bearer(s), 422, "render.accuracy_target"},
      {R"({"render": {"fidelity": "manual", "mesh_resolution": 999}})", patch_type, bearer(s), 422,
       "render.mesh_resolution"},
      {R"({"object": {"ior": 1.6}})", "text/plain", bearer(s), 415, ""},
      {R"({"object": {"ior": 1.6}})", patch_type, {}, 401, ""},
      {R"({"object": {"ior": 1.6}})", patch_type, {{"Authorization", "Bearer 0123"}}, 401, ""},
      {R"({"object": {"ior": 1.6}})", patch_type, {{"Authorization", "Basic abc"}}, 401, ""},
      {"{\"name\": \"" + std::string(70000, 'x') + "\"}", patch_type, bearer(s), 413, ""},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.body.substr(0, 60));
    expect_problem(http("PATCH", url, c.body, c.type, c.headers), c.status, c.key);
    EXPECT_EQ(http("GET", url, "", "", bearer(s)).json(), before);
  }
  // A lathe that stands clear is taken: two surfaces, two tiles.
  const Response lathe = http("PATCH", url, R"({"receivers": [{"center": [0, 0, -40], "lathe": {"profile": [[3, 0], [3, 9]]}}]})",
                              patch_type, bearer(s));
  ASSERT_EQ(lathe.status, 200u) << lathe.body;
  const json now = http("GET", url, "", "", bearer(s)).json();
  EXPECT_EQ(now["params"]["receivers"][0]["lathe"]["segments"], 64);
  EXPECT_EQ(now["atlas"].size(), 2u);
  // An unknown session answers exactly as a wrong token does.
  const Response unknown = http("PATCH", server_.url() + "/api/v1/sessions/0123456789abcdef0123456789abcdef/params",
                                R"({"object": {"ior": 1.6}})", patch_type, bearer(s));
  expect_problem(unknown, 401);
  EXPECT_EQ(unknown.body, http("PATCH", url, R"({"object": {"ior": 1.6}})", patch_type,
                               {{"Authorization", "Bearer 0123"}}).body);
  // One session's token does not open another session.
  const json other = create("slab");
  expect_problem(http("PATCH", session_url(other) + "/params", R"({"object": {"ior": 1.6}})", patch_type, bearer(s)),
                 401);
}

TEST_F(Rest, ASolidsLightGridComesBackFinerWhenATighterTargetAsksForIt) {
  // The biconvex lens's calibration holds grids of 64^2, 128^2 and 256^2
  // (its own); 64^2 misses 5% at the streamed size, 128^2 meets it. A
  // loose target takes 64^2, and 5% again must bring 128^2 back: the scene
  // patched is the resolved one, whose grid is then 64, but the bound is
  // the file's.
  const json s = create("biconvex");
  const std::string url = session_url(s) + "/params";
  const std::string patch_type = "application/merge-patch+json";
  EXPECT_EQ(s["params"]["fidelity"]["light_grid"], 128) << s["params"]["fidelity"];
  json p = http("PATCH", url, R"({"render": {"accuracy_target": 0.2}})", patch_type, bearer(s)).json();
  EXPECT_EQ(p["fidelity"]["light_grid"], 64) << p["fidelity"];
  p = http("PATCH", url, R"({"render": {"accuracy_target": 0.05}})", patch_type, bearer(s)).json();
  EXPECT_EQ(p["fidelity"]["light_grid"], 128) << p["fidelity"];
  EXPECT_EQ(p["fidelity"]["meets_target"], true) << p["fidelity"];
}

TEST_F(Rest, FidelityAutoIsTheDefaultAndSaysWhatItRenders) {
  const json s = create("lens");
  const std::string url = session_url(s) + "/params";
  const std::string patch_type = "application/merge-patch+json";
  json p = s["params"];
  const json f = p["fidelity"];
  // The built-in scenes are calibrated at build time: a coarser level than
  // the mesh as loaded meets 5% on the smooth lens.
  EXPECT_EQ(f["mode"], "auto");
  EXPECT_EQ(f["calibrated"], true);
  EXPECT_EQ(f["calibration_matches_parameters"], true);
  EXPECT_EQ(f["meets_target"], true);
  EXPECT_LE(f["expected_relative_l1"].get<double>(), 0.05);
  EXPECT_GT(f["mesh_resolution"].get<int>(), 0);
  EXPECT_EQ(f["mesh_resolution"], p["params"]["render"]["mesh_resolution"]);
  const int level = f["mesh_resolution"].get<int>();
  EXPECT_EQ(f["vertices"].get<int>(), level * level);

  // A tighter target: a finer level (or the mesh as loaded, whose vertex
  // count is not told), and an expected error within it.
  p = http("PATCH", url, R"({"render": {"accuracy_target": 0.002}})", patch_type, bearer(s)).json();
  const int finer = p["fidelity"]["mesh_resolution"].get<int>();
  EXPECT_TRUE(finer == 0 || finer > level) << finer;
  if (finer == 0) {
    EXPECT_TRUE(p["fidelity"]["vertices"].is_null()) << p["fidelity"];
  }
  EXPECT_LE(p["fidelity"]["expected_relative_l1"].get<double>(), 0.002);
  // In auto, the three settings it owns cannot be forced: they are chosen again.
  p = http("PATCH", url, R"({"render": {"fresnel": false}})", patch_type, bearer(s)).json();
  EXPECT_EQ(p["params"]["render"]["fresnel"], true);
  // Moving the light leaves the calibrated scene; the page is told.
  p = http("PATCH", url, R"({"light": {"direction": [0.1, 0, -1]}})", patch_type, bearer(s)).json();
  EXPECT_EQ(p["fidelity"]["calibration_matches_parameters"], false);
  // Manual: what is written is rendered, and its calibrated error is still shown.
  p = http("PATCH", url, R"({"render": {"fidelity": "manual", "mesh_resolution": 0, "fresnel": false}})", patch_type,
           bearer(s)).json();
  EXPECT_EQ(p["fidelity"]["mode"], "manual");
  EXPECT_EQ(p["params"]["render"]["fresnel"], false);
  EXPECT_EQ(p["fidelity"]["levels"][0], 0);
  EXPECT_GT(p["fidelity"]["expected_relative_l1"].get<double>(), 0.05);  // Fresnel off loses 8% of the flux
  EXPECT_EQ(p["fidelity"]["meets_target"], false);
  // The gallery says which levels a scene offers and whether it is calibrated.
  const json scenes = http("GET", server_.url() + "/api/v1/scenes").json()["scenes"];
  for (const auto& scene : scenes) {
    // Water is new every frame: nothing to calibrate, no coarser surface to offer.
    const bool water = scene["id"] == "pool" || scene["id"] == "pool-walls";
    EXPECT_EQ(scene["calibrated"], !water) << scene["id"];
    // A solid is no height field: its mesh is offered as loaded only.
    if (scene["proxy"]["shape"] == "solid" || water) EXPECT_EQ(scene["mesh_levels"].size(), 1u) << scene["id"];
    else EXPECT_GE(scene["mesh_levels"].size(), 2u) << scene["id"];
  }
}

TEST_F(Rest, MetricsAreExposedInPrometheusFormat) {
  create();
  const Response r = http("GET", server_.url() + "/metrics");
  ASSERT_EQ(r.status, 200u);
  EXPECT_EQ(r.content_type, "text/plain");
  for (const char* name : {"causticd_sessions 1", "causticd_sessions_created_total 1", "causticd_frames_rendered_total",
                           "causticd_render_seconds_bucket", "causticd_encode_seconds_count",
                           "causticd_parameter_updates_total", "causticd_http_errors_total",
                           "causticd_frames_dropped_total", "causticd_render_overruns_total"})
    EXPECT_NE(r.body.find(name), std::string::npos) << name;
}

TEST(RestLimits, FullServerAnswers503) {
  ServerProcess server({"--max-sessions", "2"});
  const std::string url = server.url() + "/api/v1/sessions";
  EXPECT_EQ(http("POST", url, R"({"scene": "lens"})").status, 201u);
  EXPECT_EQ(http("POST", url, R"({"scene": "slab"})").status, 201u);
  expect_problem(http("POST", url, R"({"scene": "wavy"})"), 503);
}

TEST(OpenApiDocument, MatchesTheRealResponses) {
  const caustic::testing::OpenApi api;
  ServerProcess server({"--max-sessions", "1"});
  const std::string base = server.url();
  auto check = [&](const std::string& templ, const std::string& method, const Response& r) {
    const json body = r.content_type == "image/png" || r.content_type == "text/plain" || r.body.empty()
                          ? json()
                          : r.json();
    EXPECT_EQ(api.check(templ, method, r.status, r.content_type, body), "") << method << " " << templ << " -> "
                                                                             << r.status << " " << r.body.substr(0, 200);
  };
  check("/api/v1/health", "get", http("GET", base + "/api/v1/health"));
  check("/api/v1/scenes", "get", http("GET", base + "/api/v1/scenes"));
  check("/api/v1/scenes/{id}/thumbnail.png", "get", http("GET", base + "/api/v1/scenes/lens/thumbnail.png"));
  check("/api/v1/scenes/{id}/thumbnail.png", "get", http("GET", base + "/api/v1/scenes/none/thumbnail.png"));
  check("/metrics", "get", http("GET", base + "/metrics"));
  const Response created = http("POST", base + "/api/v1/sessions", R"({"scene": "lens", "codec": "h264"})");
  check("/api/v1/sessions", "post", created);
  check("/api/v1/sessions", "post", http("POST", base + "/api/v1/sessions", R"({"scene": "slab"})"));  // 503
  check("/api/v1/sessions", "post", http("POST", base + "/api/v1/sessions", R"({"scene": 1})"));
  check("/api/v1/sessions", "post", http("POST", base + "/api/v1/sessions", "{", "application/json"));
  check("/api/v1/sessions", "post", http("POST", base + "/api/v1/sessions", "{}", "text/plain"));
  const json s = created.json();
  const std::string url = base + "/api/v1/sessions/" + s["id"].get<std::string>();
  const auto auth = bearer(s);
  check("/api/v1/sessions/{id}/params", "get", http("GET", url + "/params", "", "", auth));
  check("/api/v1/sessions/{id}/params", "get", http("GET", url + "/params"));
  check("/api/v1/sessions/{id}/params", "patch",
        http("PATCH", url + "/params", R"({"post": {"exposure": 2}})", "application/merge-patch+json", auth));
  check("/api/v1/sessions/{id}/params", "patch",
        http("PATCH", url + "/params", R"({"post": {"exposure": -2}})", "application/merge-patch+json", auth));
  check("/api/v1/sessions/{id}/signal", "get", http("GET", url + "/signal?token=" + s["token"].get<std::string>()));
  check("/api/v1/sessions/{id}", "delete", http("DELETE", url, "", "", auth));
  check("/api/v1/sessions/{id}", "delete", http("DELETE", url, "", "", auth));  // 401 now
}

TEST(Sessions, IdleSessionIsReclaimed) {
  ServerProcess server({"--idle-timeout", "1"});
  ASSERT_EQ(http("POST", server.url() + "/api/v1/sessions", R"({"scene": "slab"})").status, 201u);
  EXPECT_EQ(http("GET", server.url() + "/api/v1/health").json()["sessions"], 1);
  int sessions = 1;
  for (int i = 0; i < 50 && sessions != 0; ++i) {  // at most 5 s
    g_usleep(100000);
    sessions = http("GET", server.url() + "/api/v1/health").json()["sessions"];
  }
  EXPECT_EQ(sessions, 0);
}

TEST(ServeCommand, BadConfigurationExitsNonZeroNamingTheKey) {
  const auto file = std::filesystem::temp_directory_path() / "causticd_serve_bad.conf";
  std::ofstream(file) << "port = 0\nbitrate_kbps = lots\n";
  // Bounded, and on a port of the kernel's choosing: a server that took
  // the file would listen (on 8080, named before) and the test wait on it.
  const std::string command =
      "timeout 60 " + std::string(CAUSTICD_BINARY) + " serve --bind 127.0.0.1 --config " + file.string() + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buf[512];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
  const int status = pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 2) << output;
  EXPECT_NE(output.find("bitrate_kbps"), std::string::npos) << output;
  EXPECT_NE(output.find(":2:"), std::string::npos) << output;
}
