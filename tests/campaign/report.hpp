// SPDX-License-Identifier: LGPL-2.1-or-later
// Outcome counts, figures and pass/fail checks of the campaign, per kind.
#pragma once

#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "net.hpp"

namespace campaign {

// One named rule of the server contract. It passes when no evaluation failed.
struct Check {
  long passed = 0;
  long failed = 0;
  std::string example;  // the first failure, in full
  // Failures told apart by request line and answer, a few of each rule:
  // one rule often fails for several unrelated reasons.
  std::vector<std::string> distinct;
};

class KindReport {
 public:
  explicit KindReport(std::string name) : name_(std::move(name)) {}

  // Records an outcome class ("2xx", "closed-without-answer", ...).
  void outcome(const std::string& what, long n = 1);
  void outcome_of(const Response& r);
  void figure(const std::string& key, nlohmann::json value);
  // Evaluates a rule; the first failures of each rule go to stderr in full.
  bool check(const std::string& rule, bool ok, const std::string& detail = "");
  // A timing goal: reported as met or missed, never a failure. How fast the
  // server answers depends on what else the machine runs; the campaign
  // asserts behaviour, docs/reliability.md quotes the figures.
  void goal(const std::string& name, bool met, const std::string& detail = "");

  void print() const;
  nlohmann::json to_json() const;
  int checks_passed() const;
  int checks_failed() const;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  mutable std::mutex mutex_;
  std::map<std::string, long> outcomes_;
  std::map<std::string, Check> checks_;
  nlohmann::json figures_ = nlohmann::json::object();
};

// "2xx", "4xx", ... or the kind of non-answer.
std::string outcome_class(const Response& r);

// Empty when `r` is a well-formed error document for its status (RFC 9457
// with the fields the contract names); otherwise what is wrong.
std::string problem_defect(const Response& r, bool head = false);

// A request/response pair for the failure log.
std::string describe(std::string_view request, const Response& r);

// Percentile of a sample (sorted in place); 0 for an empty one.
double percentile(std::vector<double>& v, double p);

}  // namespace campaign
