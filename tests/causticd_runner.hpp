// SPDX-License-Identifier: LGPL-2.1-or-later
// Running the causticd binary from a test, as a user would: the exit status
// and everything it printed, and a fresh scratch folder per test.
#pragma once

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <sys/wait.h>

namespace caustic::testing {

struct CommandResult {
  int status;
  std::string output;  // stdout and stderr together
};

/// Runs `CAUSTICD_BINARY args` with `env` assignments in front.
inline CommandResult causticd_with_env(const std::string& env, const std::string& args) {
  const std::string command = env + " " + std::string(CAUSTICD_BINARY) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), &pclose);
  CommandResult run{-1, ""};
  std::array<char, 4096> buf;
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe.get())) run.output.append(buf.data(), n);
  const int raw = pclose(pipe.release());
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return run;
}

inline CommandResult causticd(const std::string& args) { return causticd_with_env("", args); }

#ifdef CAUSTIC_ASSET_DIR
/// A scratch folder, the built-in scenes, and a refusal's two marks.
class CliTest : public ScratchDirTest {
 protected:
  static std::string scene(const std::string& name) {
    return std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + name + ".json";
  }
  /// `causticd args` exits 2 with `fragment` in what it says.
  static void expect_rejected(const std::string& args, const std::string& fragment) {
    const CommandResult r = causticd(args);
    EXPECT_EQ(r.status, 2) << args.substr(0, 300) << "\n" << r.output;
    EXPECT_NE(r.output.find(fragment), std::string::npos) << args.substr(0, 300) << "\n" << r.output;
  }
};
#endif

}  // namespace caustic::testing
