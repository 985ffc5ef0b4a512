// SPDX-License-Identifier: LGPL-2.1-or-later
// What the REST tests share: a server per test, a session in it, and the
// check that an error is an RFC 9457 problem document.
#pragma once

#include "server_process.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace caustic::testing {

using nlohmann::json;

inline void expect_problem(const Response& r, guint status, const std::string& key = "") {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.content_type, "application/problem+json") << r.body;
  const json body = r.json();
  ASSERT_TRUE(body.is_object()) << r.body;
  EXPECT_EQ(body["status"], status);
  EXPECT_TRUE(body["detail"].is_string());
  if (!key.empty()) {
    EXPECT_EQ(body.value("key", ""), key) << r.body;
  }
}

/// A running server; create() starts a session in it.
class Rest : public ::testing::Test {
 protected:
  json create(const std::string& scene = "lens", const std::string& codec = "vp8") {
    const Response r = http("POST", server_.url() + "/api/v1/sessions", json{{"scene", scene}, {"codec", codec}}.dump());
    EXPECT_EQ(r.status, 201u) << r.body;
    return r.json();
  }
  std::string session_url(const json& s) const { return server_.url() + "/api/v1/sessions/" + s["id"].get<std::string>(); }
  ServerProcess server_;  // with fatal criticals, as every ServerProcess
};

}  // namespace caustic::testing
