// SPDX-License-Identifier: LGPL-2.1-or-later
// Where the installed data lives (pipelines/, web/, assets/), and the
// pipeline templates in it.
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

namespace caustic::server {

/// The data folder: $CAUSTICD_DATA_DIR when set, else ../share/causticd
/// beside the running executable (true in the build tree and under any
/// install prefix). Throws ConfigError naming CAUSTICD_DATA_DIR when
/// neither is a folder: an operator's setting, not the server's failure.
std::filesystem::path data_dir();

/// Reads pipelines/<codec>.pipeline, drops comment lines, and replaces each
/// {name} by its value. Throws std::runtime_error for an unknown codec, a
/// placeholder without a value, or a value that is not a plain token
/// (letters, digits, '.', '-', '_', '/'), so no value can inject elements.
std::string pipeline_description(const std::filesystem::path& data, const std::string& codec,
                                 const std::map<std::string, std::string>& values);

}  // namespace caustic::server
