// SPDX-License-Identifier: LGPL-2.1-or-later
// docs/scene-format.md's tables against the scene reader: each section
// lists the keys a scene has, with their defaults, and the ranges it states
// are the ones the reader holds ("number in [1, 10]": 1 and 10 taken, a
// hair beyond either refused naming the key).
#include "caustic/scene.hpp"
#include "doc_text.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <regex>

using caustic::Scene;
using caustic::SceneError;
using namespace caustic::testing;
using nlohmann::json;

namespace {

struct Section {
  const char* heading;
  const char* key;  ///< "" for the top level
};
constexpr Section kSections[] = {{"## Top level", ""},      {"## `object`", "object"}, {"## `light`", "light"},
                                 {"## `screen`", "screen"}, {"## `water`", "water"},   {"## `render`", "render"},
                                 {"## `post`", "post"}};

struct Row {
  std::vector<std::string> keys;
  std::string type, fallback;
};

std::vector<Row> rows(const Section& section) {
  std::vector<Row> out;
  static const std::string text = read_doc(std::string(CAUSTIC_SOURCE_DIR) + "/docs/scene-format.md");
  for (const auto& cells : doc_table(text, section.heading))
    if (cells.size() >= 3) out.push_back({code_spans(cells[0]), cells[1], cells[2]});
  return out;
}

// The scene a reader makes of nothing: every default, and the pool's.
json defaults(const Section& section) {
  Scene scene;
  if (std::string(section.key) == "water") scene.water.emplace();
  const json all = caustic::scene_to_json(scene);
  return *section.key ? all[section.key] : all;
}

// The key that refusing `value` at section.key names; nullopt when taken.
std::optional<std::string> refusal(const Section& section, const std::string& key, const json& value) {
  json scene = {{"mesh", "face.obj"}};
  if (std::string(section.key) == "water") scene = {{"water", json::object()}};
  (*section.key ? scene[section.key][key] : scene[key]) = value;
  try {
    caustic::scene_from_json(scene, "/nonexistent");
    return std::nullopt;
  } catch (const SceneError& e) {
    return e.key();
  }
}

}  // namespace

TEST(DocsScene, EachTableListsItsSectionsKeys) {
  for (const Section& section : kSections) {
    std::set<std::string> documented, read;
    for (const Row& row : rows(section)) documented.insert(row.keys.begin(), row.keys.end());
    const json scene = defaults(section);
    for (const auto& [key, value] : scene.items()) read.insert(key);
    // The receivers have a section of their own rather than a row.
    if (!*section.key) documented.insert("receivers");
    EXPECT_EQ(documented, read) << section.heading;
  }
}

TEST(DocsScene, EachTableStatesTheDefaults) {
  int checked = 0;
  for (const Section& section : kSections) {
    const json read = defaults(section);
    for (const Row& row : rows(section)) {
      // "`[0, 0, -100]` (or from `focus_distance`)", "1.5", "null"; "-" and "see below" are no value.
      const auto spans = code_spans(row.fallback);
      const json stated = json::parse(spans.empty() ? row.fallback : spans[0], nullptr, false);
      if (stated.is_discarded()) continue;
      for (const std::string& key : row.keys) {
        EXPECT_EQ(stated, read[key]) << section.heading << " " << key;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(DocsScene, TheRangesStatedAreTheReaders) {
  // "number in [0.5, 1]", "integer in [16, 8192]", "number in (0, 1e4]", "number > 0".
  static const std::regex interval("(number|integer) in ([\\[(])(-?[0-9.e]+), (-?[0-9.e]+)([\\])])");
  static const std::regex positive("^number > 0");
  int checked = 0;
  for (const Section& section : kSections) {
    const bool water = std::string(section.key) == "water";
    for (const Row& row : rows(section)) {
      std::string type = row.type;
      for (std::size_t at; (at = type.find("\xE2\x88\x92")) != std::string::npos;) type.replace(at, 3, "-");  // U+2212
      for (const std::string& key : row.keys) {
        const std::string named = *section.key ? std::string(section.key) + "." + key : key;
        std::smatch m;
        if (std::regex_search(type, m, interval)) {
          const bool integer = m[1] == "integer", lo_in = m[2] == "[", hi_in = m[5] == "]";
          const double lo = std::stod(m[3]), hi = std::stod(m[4]);
          const double step = integer ? 1 : 1e-6 * std::max(1.0, std::abs(lo));
          const double hi_step = integer ? 1 : 1e-6 * std::max(1.0, std::abs(hi));
          // An integer key takes JSON integers only.
          const auto value = [&](double v) { return integer ? json(std::llround(v)) : json(v); };
          EXPECT_EQ(refusal(section, key, value(lo_in ? lo - step : lo)), named) << named << " below " << lo;
          EXPECT_EQ(refusal(section, key, value(hi_in ? hi + hi_step : hi)), named) << named << " above " << hi;
          // The pool's keys bound each other (a drop no wider than a quarter
          // of the pool): its ends alone need not make a pool.
          if (!water) {
            EXPECT_EQ(refusal(section, key, value(lo_in ? lo : lo + step)), std::nullopt) << named << " = " << lo;
            EXPECT_EQ(refusal(section, key, value(hi_in ? hi : hi - hi_step)), std::nullopt) << named << " = " << hi;
          }
          ++checked;
        } else if (std::regex_search(type, positive)) {
          EXPECT_EQ(refusal(section, key, 0.0), named) << named << " = 0";
          EXPECT_EQ(refusal(section, key, 1.0), std::nullopt) << named << " = 1";
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 25);
}
