// SPDX-License-Identifier: LGPL-2.1-or-later
// The strict reader behind every scene section (scene_json.cpp,
// water_json.cpp): typed values checked for finiteness and range, messages
// that name the key, and the keys left unread reported as unknown.
#pragma once

#include "caustic/json_text.hpp"
#include "caustic/scene.hpp"
#include "caustic/shown_text.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <utility>

namespace caustic::detail {

using nlohmann::json;

/// A table of an enum's JSON names: parsing and writing both read it.
template <typename Enum>
using Names = std::span<const std::pair<const char*, Enum>>;

inline std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// Walks one JSON object, handing out typed values and remembering which keys
// were read so that anything left over is reported as unknown.
class Reader {
 public:
  Reader(const json& j, std::string path) : j_(j), path_(std::move(path)) {
    if (!j_.is_object()) throw SceneError(path_, "must be a JSON object");
  }

  bool has(const std::string& key) const { return j_.contains(key) && !j_.at(key).is_null(); }

  const json* get(const std::string& key) {
    seen_.insert(key);
    auto it = j_.find(key);
    return it == j_.end() || it->is_null() ? nullptr : &*it;
  }

  std::string key(const std::string& k) const { return join(path_, k); }

  double number(const std::string& k, double fallback, double lo, double hi, bool open_lo = false) {
    const json* v = get(k);
    if (!v) return fallback;
    if (!v->is_number()) throw SceneError(key(k), "must be a number");
    const double x = v->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi || (open_lo && x == lo)) {
      std::ostringstream msg;
      msg << "must be a finite number in " << (open_lo ? "(" : "[") << lo << ", " << hi << "], got " << x;
      throw SceneError(key(k), msg.str());
    }
    return x;
  }

  std::optional<double> optional_number(const std::string& k, double lo, double hi, bool open_lo = false) {
    if (!has(k)) {
      get(k);
      return std::nullopt;
    }
    return number(k, 0.0, lo, hi, open_lo);
  }

  int integer(const std::string& k, int fallback, int lo, int hi) {
    const json* v = get(k);
    if (!v) return fallback;
    // A whole number past 2^64 is held as a double: out of range, not "no integer".
    const bool whole = v->is_number_float() && std::isfinite(v->get<double>()) &&
                       v->get<double>() == std::floor(v->get<double>());
    if (whole && (v->get<double>() < lo || v->get<double>() > hi))
      throw SceneError(key(k), "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v->dump());
    if (!v->is_number_integer()) throw SceneError(key(k), "must be an integer");
    // Beyond long long (an unsigned 2^64 - 1) it would wrap: said as written.
    const bool huge = v->is_number_unsigned() && v->get<unsigned long long>() > static_cast<unsigned long long>(hi);
    const auto x = huge ? static_cast<long long>(hi) + 1 : v->get<long long>();
    if (x < lo || x > hi)
      throw SceneError(key(k), "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                   v->dump());
    return static_cast<int>(x);
  }

  bool boolean(const std::string& k, bool fallback) {
    const json* v = get(k);
    if (!v) return fallback;
    if (!v->is_boolean()) throw SceneError(key(k), "must be true or false");
    return v->get<bool>();
  }

  std::string string(const std::string& k, const std::string& fallback, std::size_t max_len = 4096) {
    const json* v = get(k);
    if (!v) return fallback;
    if (!v->is_string()) throw SceneError(key(k), "must be a string");
    auto s = v->get<std::string>();
    // Bytes of UTF-8, as every text limit of the project counts them.
    if (s.size() > max_len) throw SceneError(key(k), "is longer than " + std::to_string(max_len) + " bytes");
    return s;
  }

  /// A string shown to people (a title, a description): as string(), and
  /// without control characters, as the designer's --name and an upload's
  /// name are (a NUL or an escape sequence in a gallery title).
  std::string text(const std::string& k, std::size_t max_len) {
    std::string s = string(k, "", max_len);
    if (holds_control_characters(s)) throw SceneError(key(k), "must not hold control characters");
    return s;
  }

  template <typename Enum>
  Enum choice(const std::string& k, Enum fallback, Names<Enum> options) {
    const json* v = get(k);
    if (!v) return fallback;
    std::string allowed;
    for (const auto& [name, value] : options) {
      if (v->is_string() && v->get<std::string>() == name) return value;
      allowed += (allowed.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    throw SceneError(key(k), "must be one of " + allowed);
  }

  glm::dvec3 vec3(const std::string& k, glm::dvec3 fallback, bool unit = false) {
    const json* v = get(k);
    if (!v) return fallback;
    if (!v->is_array() || v->size() != 3) throw SceneError(key(k), "must be an array of 3 numbers");
    glm::dvec3 out;
    for (int i = 0; i < 3; ++i) {
      const json& e = (*v)[i];
      if (!e.is_number() || !std::isfinite(e.get<double>()) || std::abs(e.get<double>()) > kMaxCoordinate)
        throw SceneError(key(k), "must hold 3 finite numbers of magnitude at most 1e6");
      out[i] = e.get<double>();
    }
    if (unit) {
      const double len = glm::length(out);
      if (!(len > 1e-9)) throw SceneError(key(k), "must not be the zero vector");
      out /= len;
    }
    return out;
  }

  Reader child(const std::string& k) {
    static const json empty = json::object();
    const json* v = get(k);
    return Reader(v ? *v : empty, key(k));
  }

  void reject_unknown() const {
    for (const auto& [k, _] : j_.items())
      if (!seen_.count(k)) throw SceneError(key(printable_name(k)), "unknown key");
  }

 private:
  const json& j_;
  std::string path_;
  std::set<std::string> seen_;
};

}  // namespace caustic::detail
