// SPDX-License-Identifier: LGPL-2.1-or-later
// docs/configuration.md's table against the settings themselves: every key
// once, its default, the ranges it states, the flags `causticd serve`
// takes; the shipped file's values; and the keys a reload keeps, as the
// server keeps them, in the shipped file and docs/operations.md.
#include "caustic/server/config.hpp"
#include "causticd_runner.hpp"
#include "doc_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>

using namespace caustic::server;
using namespace caustic::testing;

namespace {

const std::string kRoot = CAUSTIC_SOURCE_DIR;

struct Row {
  std::vector<std::string> keys, defaults, flags;
  std::string meaning;
};

std::vector<Row> config_table() {
  std::vector<Row> rows;
  for (const auto& cells : doc_table(read_doc(kRoot + "/docs/configuration.md"), "# Configuring causticd serve"))
    if (cells.size() >= 4) rows.push_back({code_spans(cells[0]), code_spans(cells[2]), code_spans(cells[1]), cells[3]});
  return rows;
}

bool accepted(const std::string& key, const std::string& value) {
  ServerConfig c;
  try {
    set_config_value(c, key, value);
    return true;
  } catch (const ConfigError&) {
    return false;
  }
}

}  // namespace

TEST(DocsConfig, TheTableListsEveryKeyOnce) {
  std::vector<std::string> documented;
  for (const Row& row : config_table()) documented.insert(documented.end(), row.keys.begin(), row.keys.end());
  std::vector<std::string> keys = config_keys();
  std::sort(documented.begin(), documented.end());
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(documented, keys);
}

TEST(DocsConfig, TheTableStatesTheDefaults) {
  int checked = 0;
  for (const Row& row : config_table()) {
    for (std::size_t i = 0; i < row.keys.size(); ++i) {
      const std::string& key = row.keys[i];
      // "none", "any", "all interfaces": the key left empty; "<data>/web", "see below": said in prose.
      std::string value;
      if (!row.defaults.empty()) {
        value = row.defaults[std::min(i, row.defaults.size() - 1)];
        if (value.rfind("<", 0) == 0) continue;
      } else if (row.keys[0] == "state_dir") {
        continue;
      }
      ServerConfig written;
      ASSERT_NO_THROW(set_config_value(written, key, value)) << key << " = " << value;
      written.warnings.clear();
      EXPECT_TRUE(written == ServerConfig{}) << key << ": the table's default " << value << " is not the code's";
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(DocsConfig, TheRangesStatedAreTheCodes) {
  // "(10..604800)", "16..4096": the ends are taken, one beyond them is not.
  static const std::regex range("(-?[0-9]+)\\.\\.([0-9]+)");
  int checked = 0;
  for (const Row& row : config_table()) {
    std::smatch m;
    if (!std::regex_search(row.meaning, m, range)) continue;
    const long lo = std::stol(m[1]), hi = std::stol(m[2]);
    for (const std::string& key : row.keys) {
      // ice_port_range's ends are ports of a "lo-hi" pair.
      const auto text = [&](long v) { return key == "ice_port_range" ? std::to_string(v) + "-" + std::to_string(v)
                                                                     : std::to_string(v); };
      EXPECT_TRUE(accepted(key, text(lo))) << key << " = " << lo;
      EXPECT_TRUE(accepted(key, text(hi))) << key << " = " << hi;
      EXPECT_FALSE(accepted(key, text(lo - 1))) << key << " = " << lo - 1;
      EXPECT_FALSE(accepted(key, text(hi + 1))) << key << " = " << hi + 1;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10);
}

TEST(DocsConfig, TheFlagsAreServes) {
  // "--port TEXT   Overrides the config key port"
  const CommandResult help = causticd("serve --help");
  ASSERT_EQ(help.status, 0) << help.output;
  static const std::regex overrides("(--[a-z-]+) [A-Z]+ +Overrides the config key ([a-z_]+)");
  std::map<std::string, std::string> flag_of;
  for (std::sregex_iterator it(help.output.begin(), help.output.end(), overrides), end; it != end; ++it)
    flag_of[(*it)[2]] = (*it)[1];
  ASSERT_GT(flag_of.size(), 10u) << help.output;
  for (const Row& row : config_table()) {
    for (std::size_t i = 0; i < row.keys.size(); ++i) {
      const std::string& key = row.keys[i];
      const std::string flag = row.flags.empty() ? "" : row.flags[std::min(i, row.flags.size() - 1)];
      if (flag_of.count(key)) {
        EXPECT_EQ(flag, flag_of[key]) << key;
        flag_of.erase(key);
      } else if (!flag.empty()) {
        // A flag of its own kind (--ice-address, repeated) is still one serve takes.
        EXPECT_NE(help.output.find("  " + flag + " "), std::string::npos) << key << ": serve has no " << flag;
      }
    }
  }
  for (const auto& [key, flag] : flag_of) ADD_FAILURE() << flag << " sets " << key << ", which the table does not say";
}

TEST(DocsConfig, TheShippedFileWritesEveryDefault) {
  ServerConfig shipped;
  load_config_file(shipped, kRoot + "/systemd/causticd.conf");
  shipped.warnings.clear();
  EXPECT_TRUE(shipped == ServerConfig{}) << "systemd/causticd.conf writes a value that is not the default";
}

TEST(DocsConfig, TheKeysAReloadKeepsAreNamedAlike) {
  // The server's list: keep("bind_address", &ServerConfig::bind_address); in Server::reload.
  const std::string server = read_doc(kRoot + "/src/server/server.cpp");
  static const std::regex keep("keep\\(\"([a-z_]+)\", &ServerConfig::");
  std::set<std::string> kept;
  for (std::sregex_iterator it(server.begin(), server.end(), keep), end; it != end; ++it) kept.insert((*it)[1]);
  ASSERT_GT(kept.size(), 5u);
  // The passage of each document that ends in "need a restart", the keys it names.
  const auto named = [&](const std::string& file, const std::string& from) {
    // One line, the conf's comment marks gone: "need a\n# restart".
    const std::string text = std::regex_replace(read_doc(kRoot + file), std::regex("\\s*\n#?\\s*"), " ");
    const auto begin = text.find(from), end = text.find("need a restart", begin);
    std::set<std::string> keys;
    if (begin == std::string::npos || end == std::string::npos) {
      ADD_FAILURE() << file << " no longer says which keys need a restart";
      return keys;
    }
    const std::string passage = text.substr(begin, end - begin);
    for (const std::string& key : config_keys())
      if (std::regex_search(passage, std::regex("(^|[^a-z_])" + key + "([^a-z_]|$)"))) keys.insert(key);
    return keys;
  };
  EXPECT_EQ(named("/systemd/causticd.conf", "apply it with"), kept);
  EXPECT_EQ(named("/docs/operations.md", "apply to new sessions."), kept);
}
