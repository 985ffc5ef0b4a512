// SPDX-License-Identifier: LGPL-2.1-or-later
// The files of a design's folder: small helpers for reading and replacing
// them whole, and what of its report a visitor may see.
#pragma once

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace caustic::server {

/// The most bytes read of a design's file: its pictures and JSON are a few
/// hundred kilobytes.
inline constexpr std::size_t kMaxDesignFileBytes = std::size_t{16} << 20;

/// The whole file, or "" when it cannot be read, is no regular file (a
/// pipe would hold the start, a link to a device feed it without end), or
/// holds more than `limit` bytes.
std::string read_text(const std::filesystem::path& file, std::size_t limit = kMaxDesignFileBytes);

/// A file of a design that could not be stored: `error` is the errno of the
/// call that failed, what() names the file alone (never a path).
struct StorageError : std::runtime_error {
  StorageError(int error, const std::string& what) : std::runtime_error(what), error(error) {}
  /// The filesystem is full, the server's quota spent, or its file size
  /// limit (RLIMIT_FSIZE, systemd's LimitFSIZE=) reached: it passes once
  /// designs expire or the operator makes room. Anything else (EIO, EROFS)
  /// is a fault of the disk or the mount.
  bool no_room() const { return error == ENOSPC || error == EDQUOT || error == EFBIG; }
  int error;
};

/// Written under a temporary name, synced, then renamed: a crash leaves the
/// old file or the new one, never half of one. Every write, the sync and the
/// close are checked (a full disk often shows only at the close); on a
/// failure the temporary is removed and StorageError thrown.
void write_atomic(const std::filesystem::path& file, const std::string& text);

/// What a visitor may learn of a design: how well the glass forms the
/// picture and how long it took; the face's own figures (relief, slopes,
/// thickness) describe the hidden mesh and stay on the server.
nlohmann::json public_report(const nlohmann::json& report);

}  // namespace caustic::server
