// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/server/data_files.hpp"

#include "caustic/server/config.hpp"

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include <unistd.h>

namespace caustic::server {

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("CAUSTICD_DATA_DIR"); env && *env) {
    if (!std::filesystem::is_directory(env))
      throw ConfigError(std::string("CAUSTICD_DATA_DIR: ") + env + " is not a folder");
    return env;
  }
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const auto beside = exe.parent_path().parent_path() / "share" / "causticd";
  if (!ec && std::filesystem::is_directory(beside)) return beside;
  throw ConfigError("CAUSTICD_DATA_DIR: not set, and " +
                    (ec ? std::string("the executable's own path cannot be read")
                        : beside.string() + " (beside the executable) is not a folder") +
                    "; set it to the folder that holds pipelines/ and assets/");
}

std::string pipeline_description(const std::filesystem::path& data, const std::string& codec,
                                 const std::map<std::string, std::string>& values) {
  static const std::regex codec_name("[a-z0-9]+");
  if (!std::regex_match(codec, codec_name)) throw std::runtime_error("unknown codec \"" + codec + "\"");
  const auto file = data / "pipelines" / (codec + ".pipeline");
  std::ifstream in(file);
  if (!in) throw std::runtime_error("unknown codec \"" + codec + "\" (no " + file.filename().string() + ")");
  std::string text, line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    text += line.substr(first) + " ";
  }
  static const std::regex token("[A-Za-z0-9._/-]+");
  static const std::regex placeholder("\\{([a-z0-9_]+)\\}");
  std::string out;
  auto begin = std::sregex_iterator(text.begin(), text.end(), placeholder);
  std::size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1];
    const auto value = values.find(name);
    if (value == values.end()) throw std::runtime_error("pipeline " + codec + " needs a value for {" + name + "}");
    if (!std::regex_match(value->second, token))
      throw std::runtime_error("value for {" + name + "} is not a plain token");
    out += text.substr(last, static_cast<std::size_t>(it->position()) - last) + value->second;
    last = static_cast<std::size_t>(it->position() + it->length());
  }
  out += text.substr(last);
  if (out.find_first_of("{}") != std::string::npos)
    throw std::runtime_error("pipeline " + codec + " has a malformed placeholder");
  return out;
}

}  // namespace caustic::server
