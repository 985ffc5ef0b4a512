// SPDX-License-Identifier: LGPL-2.1-or-later
// The mountpoints a server has in Janus, listed in its state folder: the
// secrets that destroy them are known only to the process that made them,
// so a server killed before it destroyed them (SIGKILL, the OOM killer, a
// crash) would leave them in a Janus that keeps running. The next start
// reads the list and destroys what it names (broadcast.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

namespace caustic::server {

struct ServerState;

/// Mountpoint id to its secret.
using MountpointLedger = std::map<std::uint64_t, std::string>;

/// The length of a mountpoint's secret (random_hex(): lowercase hex).
constexpr std::size_t kMountpointSecretLength = 32;

/// The ledger's file in the state folder `folder`.
std::filesystem::path ledger_file(const std::filesystem::path& folder);

/// Writes `ledger` to `file` at once (a temporary file renamed over it,
/// mode 0600: it holds the secrets), creating the folder if need be; ""
/// when done, else why not.
std::string write_ledger(const std::filesystem::path& file, const MountpointLedger& ledger);

/// The mountpoints that `file` lists: none when it does not exist. One
/// that cannot be read or is damaged (not a regular file, over 1 MiB, not
/// JSON, fields of other types, an id that is not a positive integer, a
/// secret that is not one of ours) lists none, and `*problem` says why.
/// Beyond `limit` entries (more than the server ever holds), only the first
/// `limit` are listed, and `*problem` says so.
MountpointLedger read_ledger(const std::filesystem::path& file, std::size_t limit, std::string* problem);

/// Writes the ledger of `s` (when it has broadcasts) to its state folder:
/// every mountpoint that Janus has or may have (running, being created,
/// being destroyed). A failure is logged, once until a write succeeds again.
void record_mountpoints(const ServerState& s);

}  // namespace caustic::server
