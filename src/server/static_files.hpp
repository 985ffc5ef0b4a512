// SPDX-License-Identifier: LGPL-2.1-or-later
// Files from web/, and nothing else: no "..", no encoded escapes, no
// symbolic links, no hidden files.
#pragma once

#include "metrics.hpp"

#include <libsoup/soup.h>

#include <filesystem>
#include <optional>
#include <string>

namespace caustic::server {

/// The file under `root` that the URL path names, or nothing when the path
/// is malformed, escapes `root`, crosses a symbolic link or names no
/// regular file. "/" and folder paths map to their index.html.
std::optional<std::filesystem::path> resolve_static(const std::filesystem::path& root, const std::string& url_path);

/// Answers a GET of a file under `root`; pages may also connect to
/// `connect_also`'s origin (the broadcast server, http_util.hpp). Files
/// carry an ETag and Cache-Control: no-cache; a request whose
/// If-None-Match names the file's ETag is answered 304 without the bytes.
void serve_static(const std::filesystem::path& root, const std::string& url_path, SoupServerMessage* msg,
                  Metrics& metrics, const std::string& connect_also = "");

}  // namespace caustic::server
