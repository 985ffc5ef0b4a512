// SPDX-License-Identifier: LGPL-2.1-or-later
// A file replaced whole: written under a temporary name beside it, then
// renamed over it, so that a server killed part way leaves the old file
// or the new one, never half of one. Designs and the list of mountpoints
// in Janus are kept this way in the state folder.
#pragma once

#include <sys/types.h>

#include <cerrno>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace caustic::server {

/// A file that could not be stored: `error` is the errno of the call that
/// failed, what() names the file alone (never a path).
struct StorageError : std::runtime_error {
  StorageError(int error, const std::string& what) : std::runtime_error(what), error(error) {}
  /// The filesystem is full, the server's quota spent, or its file size
  /// limit (RLIMIT_FSIZE, systemd's LimitFSIZE=) reached: it passes once
  /// designs expire or the operator makes room. Anything else (EIO, EROFS)
  /// is a fault of the disk or the mount.
  bool no_room() const { return error == ENOSPC || error == EDQUOT || error == EFBIG; }
  int error;
};

/// Writes `text` to `file` under the name `file`.part, with permissions
/// `mode` (a temporary left by an earlier run gets them too; a link in its
/// place is refused, not followed), synced when `sync`, then renamed over
/// `file`. Every write, the sync and the close are checked (a full disk
/// often shows only at the close); on a failure the temporary is removed
/// and StorageError thrown. Without `sync` the file survives the process
/// but not necessarily a crash of the machine.
void write_atomic(const std::filesystem::path& file, const std::string& text, mode_t mode = 0644, bool sync = true);

}  // namespace caustic::server
