// Running the causticd binary from a test, as a user would: the exit status
// and everything it printed, and a fresh scratch folder per test.
#pragma once

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

/// An empty folder in the temporary directory named after `prefix` and the
/// running test.
inline std::filesystem::path fresh_test_dir(const std::string& prefix) {
  const auto dir = std::filesystem::temp_directory_path() /
                   (prefix + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace caustic::testing
