// SPDX-License-Identifier: LGPL-2.1-or-later
#include "glass_json.hpp"

#include "caustic/json_text.hpp"

#include <cmath>
#include <sstream>

namespace caustic {
namespace {

using nlohmann::json;

double coefficient(const json& j, const std::string& key, double lo, double hi) {
  if (!j.is_number() || !std::isfinite(j.get<double>()) || j.get<double>() < lo || j.get<double>() > hi) {
    std::ostringstream msg;
    msg << "must be a finite number in [" << lo << ", " << hi << "]";
    throw SceneError(key, msg.str());
  }
  return j.get<double>();
}

void only_keys(const json& j, const std::string& key, std::initializer_list<const char*> allowed) {
  if (!j.is_object()) throw SceneError(key, "must be a JSON object");
  for (const auto& [k, _] : j.items()) {
    bool known = false;
    for (const char* a : allowed) known = known || k == a;
    if (!known) throw SceneError(key + "." + printable_name(k), "unknown key");
  }
}

optics::Sellmeier sellmeier_from_json(const json& j, const std::string& key) {
  only_keys(j, key, {"b", "c"});
  const auto b = j.find("b"), c = j.find("c");
  if (b == j.end() || c == j.end()) throw SceneError(key, "needs \"b\" and \"c\", arrays of 1 to 4 numbers");
  if (!b->is_array() || b->empty() || b->size() > 4) throw SceneError(key + ".b", "must be an array of 1 to 4 numbers");
  if (!c->is_array() || c->size() != b->size()) throw SceneError(key + ".c", "must be an array as long as \"b\"");
  optics::Sellmeier law;
  for (std::size_t i = 0; i < b->size(); ++i) {
    law.b[i] = coefficient((*b)[i], key + ".b", 0.0, 10.0);
    law.c[i] = coefficient((*c)[i], key + ".c", 0.0, 1e4);  // µm²: an infrared pole may lie far out
  }
  return law;
}

optics::Cauchy cauchy_from_json(const json& j, const std::string& key) {
  only_keys(j, key, {"a", "b"});
  if (!j.contains("a") || !j.contains("b")) throw SceneError(key, "needs \"a\" and \"b\"");
  return {coefficient(j.at("a"), key + ".a", 1.0, 10.0), coefficient(j.at("b"), key + ".b", 0.0, 1.0)};
}

}  // namespace

double Glass::index(double nm) const {
  return std::visit([nm](const auto& law) { return optics::index(law, nm); }, law);
}

Glass glass_from_json(const json& j, const std::string& key) {
  Glass glass;
  if (j.is_string()) {
    const auto* m = optics::find_material(j.get<std::string>());
    if (!m) {
      std::string names;
      for (const auto& known : optics::materials()) names += (names.empty() ? "\"" : ", \"") + std::string(known.name) + "\"";
      throw SceneError(key, "must be one of " + names + ", or {\"sellmeier\": ...} or {\"cauchy\": ...}");
    }
    glass.name = std::string(m->name);
    glass.law = m->law;
    return glass;
  }
  only_keys(j, key, {"sellmeier", "cauchy"});
  if (j.size() != 1) throw SceneError(key, "must hold exactly one of \"sellmeier\" or \"cauchy\"");
  if (j.contains("sellmeier"))
    glass.law = sellmeier_from_json(j.at("sellmeier"), key + ".sellmeier");
  else
    glass.law = cauchy_from_json(j.at("cauchy"), key + ".cauchy");
  // A law may have a pole (λ² = c) or fall below 1 somewhere in the visible:
  // refuse it here rather than trace a wavelength with no index. Every half
  // nanometre: the wavelengths a frame samples all lie on that grid.
  for (double nm = optics::kVisibleMinNm; nm <= optics::kVisibleMaxNm; nm += 0.5) {
    double n = 0;
    try {
      n = glass.index(nm);
    } catch (const std::invalid_argument&) {
    }
    if (!(n >= 1.0 && n <= 10.0))
      throw SceneError(key, "gives no index in [1, 10] at " + json(nm).dump() + " nm");
  }
  return glass;
}

json glass_to_json(const Glass& glass) {
  if (!glass.name.empty()) return glass.name;
  if (const auto* s = std::get_if<optics::Sellmeier>(&glass.law)) {
    json b = json::array(), c = json::array();
    for (std::size_t i = 0; i < s->b.size(); ++i)
      if (s->b[i] != 0 || s->c[i] != 0) {
        b.push_back(s->b[i]);
        c.push_back(s->c[i]);
      }
    if (b.empty()) b.push_back(0.0), c.push_back(0.0);
    return {{"sellmeier", {{"b", b}, {"c", c}}}};
  }
  const auto& cauchy = std::get<optics::Cauchy>(glass.law);
  return {{"cauchy", {{"a", cauchy.a}, {"b", cauchy.b}}}};
}

}  // namespace caustic
