// SPDX-License-Identifier: LGPL-2.1-or-later
// Generator of hostile HTTP requests against every endpoint (the
// "malformed" kind). Deterministic for a seed.
#pragma once

#include <functional>
#include <random>
#include <string>
#include <vector>

#include "report.hpp"

namespace campaign {

struct Case {
  std::string category;
  std::string bytes;
  bool broken = false;      // not valid HTTP: closing without an answer is acceptable
  bool half_close = false;  // promises more than it sends: shut our side so nobody waits for the timeout
  bool head = false;
  // 0: leaves no state to compare; 1: if refused, the victim's state must be
  // unchanged; 2: must leave it unchanged whatever the answer.
  int state = 0;
  // An extra rule for this case; the name of the rule and whether it held.
  std::function<void(KindReport&, const Response&, const std::string& shown)> rule;
};

// The session the cases aim at, and what it looks like.
struct Victim {
  std::string id;
  std::string token;
  std::string scene;
  nlohmann::json params;  // the "params" object of GET .../params
};

class CaseGenerator {
 public:
  CaseGenerator(unsigned seed, Victim victim);
  Case next();
  void set_victim(Victim v);

 private:
  Case method_case();
  Case request_line_case();
  Case header_case();
  Case length_case();
  Case body_case();
  Case auth_case();
  Case patch_value_case();
  Case static_case();
  Case handshake_case();

  std::string endpoint();
  std::string pick(const std::vector<std::string>& v);
  std::string random_id();
  std::string valid_patch();
  Case patch(const std::string& body, const std::string& type = "application/merge-patch+json");

  std::mt19937 rng_;
  Victim victim_;
  std::vector<std::pair<std::vector<std::string>, nlohmann::json>> leaves_;
  unsigned counter_ = 0;
};

}  // namespace campaign
