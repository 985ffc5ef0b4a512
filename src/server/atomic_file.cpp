// SPDX-License-Identifier: LGPL-2.1-or-later
#include "atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>

namespace caustic::server {

void write_atomic(const std::filesystem::path& file, const std::string& text, mode_t mode, bool sync) {
  const std::filesystem::path part = file.string() + ".part";
  const auto fail = [&](int error, int fd) {
    if (fd >= 0) ::close(fd);
    ::unlink(part.c_str());
    throw StorageError(error, "cannot write " + file.filename().string() + ": " + std::strerror(error));
  };
  const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, mode);
  if (fd < 0) fail(errno, -1);
  if (::fchmod(fd, mode) != 0) fail(errno, fd);
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    // A write that takes nothing without an error would loop for ever: no room.
    if (n <= 0) fail(n < 0 ? errno : ENOSPC, fd);
    done += static_cast<std::size_t>(n);
  }
  // Where space is reserved late (network and copy-on-write filesystems,
  // quotas) the sync or the close is the first to say there was none.
  if (sync && ::fsync(fd) != 0) fail(errno, fd);
  if (::close(fd) != 0) fail(errno, -1);
  if (::rename(part.c_str(), file.c_str()) != 0) fail(errno, -1);
}

}  // namespace caustic::server
