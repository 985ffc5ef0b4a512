// SPDX-License-Identifier: LGPL-2.1-or-later
#include "static_files.hpp"

#include "http_util.hpp"

#include "caustic/fnv1a.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <sstream>

namespace caustic::server {

std::optional<std::filesystem::path> resolve_static(const std::filesystem::path& root, const std::string& url_path) {
  namespace fs = std::filesystem;
  // The path comes still percent-encoded (request_path()): decode once, and
  // refuse anything that decodes to a separator trick or a control byte. An
  // encoded slash would name a file with "/" in its name: there is none.
  for (std::size_t at = url_path.find('%'); at != std::string::npos; at = url_path.find('%', at + 1))
    if (at + 2 < url_path.size() && url_path[at + 1] == '2' && (url_path[at + 2] == 'F' || url_path[at + 2] == 'f'))
      return std::nullopt;
  gchar* decoded_c = g_uri_unescape_string(url_path.c_str(), nullptr);
  if (!decoded_c) return std::nullopt;
  const std::string decoded = decoded_c;
  g_free(decoded_c);
  if (decoded.empty() || decoded[0] != '/' || decoded.find('\\') != std::string::npos ||
      decoded.find('\0') != std::string::npos || decoded.find('%') != std::string::npos)
    return std::nullopt;
  for (unsigned char ch : decoded)
    if (ch < 0x20 || ch == 0x7f) return std::nullopt;
  // One name per file: no empty segment, and a trailing '/' only on a folder.
  if (decoded.find("//") != std::string::npos) return std::nullopt;
  const bool folder_asked = decoded.size() > 1 && decoded.back() == '/';
  fs::path relative;
  std::istringstream parts(decoded.substr(1));
  for (std::string part; std::getline(parts, part, '/');) {
    if (part.empty()) continue;
    if (part[0] == '.') return std::nullopt;  // "..", "." and hidden files alike
    relative /= part;
  }
  std::error_code ec;
  const fs::path base = fs::canonical(root, ec);
  if (ec) return std::nullopt;
  fs::path candidate = base / relative;
  if (fs::is_directory(fs::symlink_status(candidate, ec))) candidate /= "index.html";
  else if (folder_asked) return std::nullopt;
  // Every component must be what it says: a canonical path that differs
  // from the lexical one went through a symbolic link.
  const fs::path real = fs::canonical(candidate, ec);
  if (ec || real != candidate.lexically_normal() || !fs::is_regular_file(fs::symlink_status(real, ec)))
    return std::nullopt;
  return real;
}

namespace {

// The policy for one page: the import map that lets modules say "three" is
// an inline script, which script-src 'self' blocks; its hash admits exactly
// that text and nothing injected beside it.
std::string page_policy(const std::string& html) {
  std::string hashes;
  for (std::size_t at = html.find("<script"); at != std::string::npos; at = html.find("<script", at + 1)) {
    const auto open_end = html.find('>', at);
    if (open_end == std::string::npos) break;
    if (html.substr(at, open_end - at).find(" src=") != std::string::npos) continue;
    const auto close = html.find("</script>", open_end);
    if (close == std::string::npos) break;
    const std::string body = html.substr(open_end + 1, close - open_end - 1);
    GChecksum* sum = g_checksum_new(G_CHECKSUM_SHA256);
    g_checksum_update(sum, reinterpret_cast<const guchar*>(body.data()), static_cast<gssize>(body.size()));
    guint8 digest[32];
    gsize length = sizeof digest;
    g_checksum_get_digest(sum, digest, &length);
    g_checksum_free(sum);
    gchar* b64 = g_base64_encode(digest, length);
    hashes += std::string(" 'sha256-") + b64 + "'";
    g_free(b64);
  }
  std::string policy = kContentSecurityPolicy;
  const std::string script = "script-src 'self'";
  if (const auto pos = policy.find(script); pos != std::string::npos) policy.insert(pos + script.size(), hashes);
  return policy;
}

// Pages, scripts and styles: the largest, three.js, is 1.5 MB.
constexpr off_t kLargestFile = 32 << 20;

// The file's bytes, opened without following a link in its last component
// (one put there after resolve_static() looked), and its validator: size
// and modification time, which change with every copy a build makes.
std::optional<std::string> read_regular(const std::filesystem::path& file, std::string* etag) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat st {};
  std::string bytes;
  bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size <= kLargestFile;
  if (ok) {
    bytes.resize(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    while (got < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    ok = got == bytes.size();
  }
  ::close(fd);
  if (!ok) return std::nullopt;
  char tag[64];
  std::snprintf(tag, sizeof tag, "\"%llx-%llx.%lx\"", static_cast<unsigned long long>(st.st_size),
                static_cast<unsigned long long>(st.st_mtim.tv_sec), static_cast<unsigned long>(st.st_mtim.tv_nsec));
  *etag = tag;
  return bytes;
}

}  // namespace

void serve_static(const std::filesystem::path& root, const std::string& url_path, SoupServerMessage* msg,
                  Metrics& metrics, const std::string& connect_also) {
  static const std::map<std::string, std::string> types = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript"},     {".mjs", "text/javascript"},
      {".css", "text/css"},                  {".json", "application/json"}, {".png", "image/png"},
      {".svg", "image/svg+xml"},             {".ico", "image/x-icon"},      {".txt", "text/plain; charset=utf-8"},
      {".wasm", "application/wasm"},         {".yaml", "application/yaml"}};
  const auto file = resolve_static(root, url_path);
  const auto type = file ? types.find(file->extension().string()) : types.end();
  if (!file || type == types.end()) return reply_problem(msg, metrics, SOUP_STATUS_NOT_FOUND, "no such file");
  std::string etag;
  const auto bytes = read_regular(*file, &etag);
  if (!bytes) return reply_problem(msg, metrics, SOUP_STATUS_NOT_FOUND, "no such file");
  const bool page = file->extension() == ".html";
  const std::string policy = page ? allow_connect(page_policy(*bytes), connect_also) : "";
  // A page's policy comes with it and changes with the configuration (the
  // broadcast server it may reach): part of its tag, or a 304 after a
  // reload would keep the old policy in the browser's cache.
  if (page) etag.insert(etag.size() - 1, "-" + std::to_string(fnv1a(policy)));
  SoupMessageHeaders* headers = soup_server_message_get_response_headers(msg);
  if (lists_tag(msg, "If-None-Match", etag, true)) {
    soup_server_message_set_status(msg, SOUP_STATUS_NOT_MODIFIED, nullptr);
    // The library would write the empty body's length, 0, which a cache
    // may copy onto the file it kept; only the 200's own may be sent
    // (RFC 9110 8.6).
    soup_message_headers_set_content_length(headers, bytes->size());
  } else {
    reply_bytes(msg, SOUP_STATUS_OK, type->second, bytes->data(), bytes->size());
  }
  // A 304 too: a browser copies its headers onto the page it kept (RFC 9111
  // 4.3.4), and the API's policy there would block the page's import map.
  if (page) soup_message_headers_replace(headers, "Content-Security-Policy", policy.c_str());
  // Kept, but asked about at each use: a page load after the first costs a
  // 304 per file, not three.js's megabytes again, and an upgrade's files
  // are seen at once. (The API's answers stay no-store.)
  soup_message_headers_replace(headers, "Cache-Control", "no-cache");
  soup_message_headers_replace(headers, "ETag", etag.c_str());
}

}  // namespace caustic::server
