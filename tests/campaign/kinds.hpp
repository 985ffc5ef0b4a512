// SPDX-License-Identifier: LGPL-2.1-or-later
// The fault kinds of the campaign and what they share.
#pragma once

#include <functional>
#include <random>
#include <string>
#include <vector>

#include "report.hpp"
#include "server.hpp"

namespace campaign {

struct Options {
  std::string binary;
  std::string folder;  // scratch folder for configs and server logs
  bool short_mode = false;
  unsigned seed = 20261129;
};

// Config every kind starts from: small streams (the renderer is software
// on CI), short timeouts so reclamation is observable within the run, and
// every limit the contract names, so each is in force while attacked.
Config base_config();
void set_key(Config& config, const std::string& key, const std::string& value);

// Rules every answer must follow. `broken`: the request is not valid HTTP,
// so closing without an answer is acceptable. `shed_ok`: 503/429 with
// Retry-After count as load shedding rather than as failures. `server`:
// nullptr from worker threads (the main thread watches the process).
void judge_common(KindReport& report, ServerProcess* server, std::string_view request, const Response& r, bool broken,
                  bool head = false, bool shed_ok = true);

// A session made through the public API.
struct Session {
  std::string id;
  std::string token;
  bool ok() const { return !id.empty(); }
};
Session create_session(int port, const std::string& scene, Response* answer = nullptr, const std::string& source = "");
bool delete_session(int port, const Session& s);
// Ids of the gallery's scenes ("" entries never).
std::vector<std::string> scene_ids(int port);
// Opens the session's signalling socket; an empty Conn when refused.
Conn open_signal(int port, const Session& s, std::mt19937& rng, Response* answer = nullptr);

void run_malformed(const Options& options, KindReport& report);
void run_keepalive(const Options& options, KindReport& report);
void run_slow(const Options& options, KindReport& report);
void run_flood(const Options& options, KindReport& report);
void run_sessions(const Options& options, KindReport& report);

}  // namespace campaign
