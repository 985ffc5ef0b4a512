// SPDX-License-Identifier: LGPL-2.1-or-later
// A web folder of a test's own for `causticd serve --web-dir`: the files it
// is given, in a fresh temporary folder that goes when the test ends (an
// assertion that stops the test included).
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>

namespace caustic::testing {

class WebFolder {
 public:
  /// `files`: each file's path under the folder, and its text.
  explicit WebFolder(std::initializer_list<std::pair<std::string, std::string>> files) {
    std::string name = (std::filesystem::temp_directory_path() / "causticd_web-XXXXXX").string();
    if (!::mkdtemp(name.data())) throw std::runtime_error("cannot make " + name);
    path_ = name;
    for (const auto& [file, text] : files) write(file, text);
  }
  ~WebFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  WebFolder(const WebFolder&) = delete;
  WebFolder& operator=(const WebFolder&) = delete;

  /// Writes `text` to `file` (a path under the folder), over what was there.
  void write(const std::string& file, const std::string& text) const {
    std::filesystem::create_directories((path_ / file).parent_path());
    std::ofstream(path_ / file, std::ios::binary) << text;
  }
  const std::filesystem::path& path() const { return path_; }
  /// The folder as `--web-dir` takes it.
  std::string dir() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace caustic::testing
