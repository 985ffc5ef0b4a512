// SPDX-License-Identifier: LGPL-2.1-or-later
// resolve_static maps a URL path (still percent-encoded) to a file under
// web/. The fuzzer gets a small web root with the traps a real one can hold:
// hidden files and folders, a folder without index.html, symbolic links to
// files and folders inside and outside, a FIFO. Whatever it returns must be
// a regular file strictly inside the canonical root, reached without any
// symbolic link and through no hidden component.
#include "static_files.hpp"
#include "fuzz_support.hpp"

#include <glib.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {

fs::path g_top;   // holds the root and a file outside it
fs::path g_root;  // canonical web root

void write(const fs::path& p, const char* text) { std::ofstream(p) << text; }

void remove_top() {
  std::error_code ec;
  fs::remove_all(g_top, ec);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_log_set_always_fatal(static_cast<GLogLevelFlags>(G_LOG_LEVEL_CRITICAL | G_LOG_LEVEL_ERROR));
  std::string top = (fs::temp_directory_path() / "causticd-fuzz-static-XXXXXX").string();
  if (!mkdtemp(top.data())) std::abort();
  g_top = fs::canonical(top);
  std::atexit(remove_top);
  const fs::path www = g_top / "www";
  fs::create_directories(www / "sub");
  fs::create_directories(www / ".git");
  fs::create_directories(www / "empty");
  write(www / "index.html", "<html></html>");
  write(www / "app.js", "export {};");
  write(www / ".hidden", "secret");
  write(www / ".git" / "config", "secret");
  write(www / "sub" / "index.html", "<html></html>");
  write(www / "sub" / "page.css", "body {}");
  write(www / "sub" / ".secret", "secret");
  write(g_top / "outside.txt", "secret");
  fs::create_symlink("../outside.txt", www / "link-out");
  fs::create_symlink("index.html", www / "link-in");
  fs::create_symlink("sub", www / "linkdir");
  fs::create_symlink("..", www / "linkdir-out");
  fs::create_symlink(g_top / "outside.txt", www / "sub" / "abs-link");
  if (mkfifo((www / "fifo").c_str(), 0600) != 0) std::abort();
  g_root = fs::canonical(www);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string url(reinterpret_cast<const char*>(data), size);
  // The root as configured need not be canonical: odd sizes spell it the long way.
  const fs::path root = size % 2 ? g_top / "www" / ".." / "www" / "." : g_root;
  const auto file = caustic::server::resolve_static(root, url);
  if (!file) return 0;
  FUZZ_CHECK(file->is_absolute());
  const fs::path relative = file->lexically_relative(g_root);
  FUZZ_CHECK(!relative.empty() && relative != ".");
  fs::path walked = g_root;
  for (const auto& part : relative) {
    const std::string name = part.string();
    FUZZ_CHECK(!name.empty() && name[0] != '.');  // also rules out ".." (outside) and hidden names
    walked /= part;
    struct stat st;
    FUZZ_CHECK(lstat(walked.c_str(), &st) == 0);
    FUZZ_CHECK(!S_ISLNK(st.st_mode));
  }
  FUZZ_CHECK(walked == *file);
  FUZZ_CHECK(fs::is_regular_file(fs::symlink_status(*file)));
  return 0;
}
