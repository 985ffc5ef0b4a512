// SPDX-License-Identifier: LGPL-2.1-or-later
#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace campaign {

namespace {
// Enough to show the pattern of a failure without drowning the log.
constexpr long kLoggedPerRule = 3;
constexpr size_t kDistinctPerRule = 12;

// "METHOD /path-prefix VERSION -> answer 400": what tells failures apart.
std::string signature(const std::string& detail) {
  const auto req = detail.find("request:  ");
  if (req == std::string::npos) return detail.substr(0, std::min<size_t>(detail.size(), 80));
  const auto start = req + 10;
  auto end = std::min(detail.find("\\r\\n", start), detail.find('\n', start));
  std::string line = detail.substr(start, std::min<size_t>(end - start, 60));
  // Session ids and tokens differ every time; their position is what matters.
  for (size_t i = 0; i + 32 <= line.size(); ++i)
    if (line.find_first_not_of("0123456789abcdef", i) >= i + 32) line.replace(i, 32, "{hex}");
  const auto resp = detail.find("response: ", start);
  if (resp != std::string::npos)
    line += " -> " + detail.substr(resp + 10, std::min<size_t>(detail.find('\n', resp) - resp - 10, 40));
  return line;
}
}  // namespace

void KindReport::outcome(const std::string& what, long n) {
  std::lock_guard lock(mutex_);
  outcomes_[what] += n;
}

void KindReport::outcome_of(const Response& r) { outcome(outcome_class(r)); }

void KindReport::figure(const std::string& key, nlohmann::json value) {
  std::lock_guard lock(mutex_);
  figures_[key] = std::move(value);
}

bool KindReport::check(const std::string& rule, bool ok, const std::string& detail) {
  std::lock_guard lock(mutex_);
  Check& c = checks_[rule];
  if (ok) {
    ++c.passed;
    return true;
  }
  if (c.failed == 0) c.example = detail;
  if (c.distinct.size() < kDistinctPerRule) {
    const std::string sig = signature(detail);
    if (std::find(c.distinct.begin(), c.distinct.end(), sig) == c.distinct.end()) c.distinct.push_back(sig);
  }
  if (c.failed < kLoggedPerRule) std::cerr << "FAIL [" << name_ << "] " << rule << "\n" << detail << "\n\n";
  ++c.failed;
  return false;
}

void KindReport::goal(const std::string& name, bool met, const std::string& detail) {
  std::lock_guard lock(mutex_);
  figures_["goal: " + name] = met ? "met" : "missed: " + detail;
}

void KindReport::print() const {
  std::lock_guard lock(mutex_);
  std::printf("\n== %s ==\n  outcomes:\n", name_.c_str());
  for (const auto& [k, v] : outcomes_) std::printf("    %-28s %10ld\n", k.c_str(), v);
  std::printf("  figures:\n");
  for (const auto& [k, v] : figures_.items()) std::printf("    %-36s %s\n", k.c_str(), v.dump().c_str());
  std::printf("  checks:\n");
  for (const auto& [k, c] : checks_)
    std::printf("    %-4s %-58s ok %ld, failed %ld\n", c.failed ? "FAIL" : "ok", k.c_str(), c.passed, c.failed);
}

nlohmann::json KindReport::to_json() const {
  std::lock_guard lock(mutex_);
  nlohmann::json checks = nlohmann::json::object();
  for (const auto& [k, c] : checks_) {
    checks[k] = {{"passed", c.passed}, {"failed", c.failed}};
    if (c.failed) {
      checks[k]["example"] = c.example;
      checks[k]["distinct_failures"] = c.distinct;
    }
  }
  return {{"outcomes", outcomes_}, {"figures", figures_}, {"checks", checks}};
}

int KindReport::checks_passed() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(std::count_if(checks_.begin(), checks_.end(), [](auto& c) { return c.second.failed == 0; }));
}

int KindReport::checks_failed() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(std::count_if(checks_.begin(), checks_.end(), [](auto& c) { return c.second.failed != 0; }));
}

std::string outcome_class(const Response& r) {
  if (r.kind != Response::Answer) return kind_name(r.kind);
  if (r.status == 429 || r.status == 503 || r.status == 101) return std::to_string(r.status);
  return std::to_string(r.status / 100) + "xx";
}

std::string problem_defect(const Response& r, bool head) {
  if (r.kind != Response::Answer || r.status < 400) return "";
  const std::string type = r.header("Content-Type");
  if (type.rfind("application/problem+json", 0) != 0) return "Content-Type is \"" + type + "\"";
  if (head) return "";
  const auto body = nlohmann::json::parse(r.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return "the body is not a JSON object";
  for (const char* field : {"type", "title", "detail"})
    if (!body.contains(field) || !body[field].is_string()) return std::string("no string \"") + field + "\"";
  if (!body.contains("status") || !body["status"].is_number_integer() || body["status"].get<int>() != r.status)
    return "\"status\" does not equal " + std::to_string(r.status);
  return "";
}

std::string describe(std::string_view request, const Response& r) {
  std::string out = "  request:  " + escape(request) + "\n  response: " + kind_name(r.kind);
  if (r.kind == Response::Answer) {
    out.append(" ").append(std::to_string(r.status)).append("\n");
    for (const auto& [k, v] : r.headers) out.append("    ").append(k).append(": ").append(escape(v, 200)).append("\n");
    out.append("    body: ").append(escape(r.body, 400));
  }
  return out;
}

double percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::ceil(p / 100.0 * v.size())) - (p > 0 ? 1 : 0));
  return std::round(v[i] * 100) / 100;
}

}  // namespace campaign
