// SPDX-License-Identifier: LGPL-2.1-or-later
// The files of a design's folder: reading them whole (they are replaced
// whole, atomic_file.hpp), and what of its report a visitor may see.
#pragma once

#include "atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>

namespace caustic::server {

/// The most bytes read of a design's file: its pictures and JSON are a few
/// hundred kilobytes.
inline constexpr std::size_t kMaxDesignFileBytes = std::size_t{16} << 20;

/// The whole file, or "" when it cannot be read, is no regular file (a
/// pipe would hold the start, a link to a device feed it without end), or
/// holds more than `limit` bytes.
std::string read_text(const std::filesystem::path& file, std::size_t limit = kMaxDesignFileBytes);

/// What a visitor may learn of a design: how well the glass forms the
/// picture and how long it took; the face's own figures (relief, slopes,
/// thickness) describe the hidden mesh and stay on the server.
nlohmann::json public_report(const nlohmann::json& report);

}  // namespace caustic::server
