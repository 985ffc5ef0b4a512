// SPDX-License-Identifier: LGPL-2.1-or-later
// A scratch folder per test, for tests that write files: named after the
// test, so tests running side by side never share one.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace caustic::testing {

/// A test with its own empty scratch folder, dir_, named after the test and
/// removed afterwards.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           (std::string("causticd_") + info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

}  // namespace caustic::testing
