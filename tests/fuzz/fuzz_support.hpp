// SPDX-License-Identifier: LGPL-2.1-or-later
// Shared by the fuzz targets: an in-memory file for parsers that take a
// path, and a check that turns a broken invariant into a crash libFuzzer
// records (an exception would only be one more input that "failed").
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace caustic::fuzz {

[[noreturn]] inline void fail(const char* what, const char* file, int line) {
  std::fprintf(stderr, "fuzz invariant broken at %s:%d: %s\n", file, line, what);
  std::abort();
}

#define FUZZ_CHECK(cond) ((cond) ? (void)0 : ::caustic::fuzz::fail(#cond, __FILE__, __LINE__))

/// A memfd holding the input, named by a /proc/self/fd path: parsers that
/// open a path read it without the fuzzer touching the disk per input.
class MemFile {
 public:
  MemFile(const void* data, std::size_t size) : fd_(memfd_create("fuzz-input", MFD_CLOEXEC)) {
    if (fd_ < 0) fail("memfd_create", __FILE__, __LINE__);
    const char* p = static_cast<const char*>(data);
    for (std::size_t done = 0; done < size;) {
      const ssize_t n = write(fd_, p + done, size - done);
      if (n <= 0) fail("write to memfd", __FILE__, __LINE__);
      done += static_cast<std::size_t>(n);
    }
  }
  ~MemFile() { close(fd_); }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;

  std::string path() const { return "/proc/self/fd/" + std::to_string(fd_); }

 private:
  int fd_;
};

/// True when every byte is printable ASCII: error messages promise that.
inline bool printable_ascii(const std::string& s) {
  for (unsigned char ch : s)
    if (ch < 0x20 || ch >= 0x7f) return false;
  return true;
}

}  // namespace caustic::fuzz
