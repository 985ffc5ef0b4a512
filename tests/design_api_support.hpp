// SPDX-License-Identifier: LGPL-2.1-or-later
// What the tests of visitors' pictures over the API share: a picture with a
// known oracle, uploads, bounded waits for a design and for its session, a
// state folder of their own, and the fixture that needs the designer.
#pragma once

#include "caustic/image.hpp"
#include "caustic/image_io.hpp"
#include "server_process.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace caustic::testing::design_api {

using caustic::testing::bearer_token;
using caustic::testing::http;
using caustic::testing::Response;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

// A bright square (a quarter of the side) on a dark floor: the oracle is
// where the light must go, not what the designer says it did.
inline std::string square_png(int n = 128, int level = 255) {
  caustic::Rgba8Image image{n, n, std::vector<std::uint8_t>(std::size_t(n) * n * 4, 255)};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const bool inside = std::abs(x - n / 2) < n / 4 && std::abs(y - n / 2) < n / 4;
      for (int c = 0; c < 3; ++c) image.pixels[(std::size_t(y) * n + x) * 4 + c] = inside ? level : level / 10;
    }
  const auto bytes = caustic::encode_png(image);
  return std::string(bytes.begin(), bytes.end());
}

inline Response upload(const ServerProcess& server, const std::string& body, const std::string& type = "image/png",
                const std::string& query = "", const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  return http("POST", server.url() + "/api/v1/designs" + query, body, type, headers);
}

// Polls a design until it leaves queued/designing or `seconds` pass.
inline json wait_design(const ServerProcess& server, const std::string& id, double seconds = 180) {
  json state;
  for (int i = 0; i < seconds * 5; ++i) {
    state = http("GET", server.url() + "/api/v1/designs/" + id).json();
    if (state.value("state", "") == "ready" || state.value("state", "") == "failed") return state;
    g_usleep(200000);
  }
  return state;
}

// Polls a design until it is being designed (false: not within 60 s).
inline bool wait_designing(const ServerProcess& server, const std::string& id) {
  for (int i = 0; i < 600; ++i) {
    if (http("GET", server.url() + "/api/v1/designs/" + id).json().value("state", "") == "designing") return true;
    g_usleep(100000);
  }
  return false;
}

inline void expect_problem(const Response& r, guint status, const std::string& detail_part = "") {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.content_type, "application/problem+json") << r.body;
  const json body = r.json();
  EXPECT_EQ(body.value("status", 0), static_cast<int>(status)) << r.body;
  if (!detail_part.empty()) {
    EXPECT_NE(body.value("detail", "").find(detail_part), std::string::npos) << r.body;
  }
}

inline int folders_in(const fs::path& dir) {
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) n += e.is_directory();
  return n;
}

// A session on a design, asked again while the server reads the design
// back (503), for at most 30 s.
inline Response create_session_retrying(const ServerProcess& server, const std::string& scene) {
  Response r;
  for (int i = 0; i < 300; ++i) {
    r = http("POST", server.url() + "/api/v1/sessions", json{{"scene", scene}}.dump());
    if (r.status != 503u) break;
    g_usleep(100000);
  }
  return r;
}

struct TempDir {
  fs::path path;
  TempDir() {
    gchar* p = g_dir_make_tmp("causticd-design-test-XXXXXX", nullptr);
    path = p;
    g_free(p);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

inline std::vector<std::string> small_designs(const TempDir& state) {
  return {"--set", "state_dir=" + state.path.string(), "--set", "design_resolution=128", "--set",
          "design_uploads_per_hour=1000"};
}

// The other tests need the designer.
class DesignApi : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!DESIGN_BUILT_IN) GTEST_SKIP() << "built with CAUSTICD_WITH_DESIGN=OFF";
  }
};

// A design made and finished by a server that then stops, its files left
// in `state`: its id ("" when it did not finish, which the caller checks).
inline std::string stored_design(const TempDir& state) {
  ServerProcess server(small_designs(state));
  const std::string id = upload(server, square_png()).json().value("id", "");
  return wait_design(server, id).value("state", "") == "ready" ? id : "";
}

}  // namespace caustic::testing::design_api
