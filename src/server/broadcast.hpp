// SPDX-License-Identifier: LGPL-2.1-or-later
// Broadcast sessions: rendered and encoded once, forwarded by the Janus
// WebRTC server to any number of viewers (docs/scaling.md). The session's
// holder changes the scene as usual; causticd creates a private mountpoint
// for it (random pin and secret) through Janus's admin API, re-creates it
// when Janus restarts, and destroys it with the session. Viewers get signed,
// short-lived links (POST .../viewers) and talk to Janus directly.
#pragma once

#include "gallery.hpp"

#include <libsoup/soup.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace caustic::server {

struct ServerState;
class Session;

/// What causticd knows of a broadcast's mountpoint.
struct Mountpoint {
  std::uint64_t id = 0;
  std::string secret, pin;
  int video_port = 0, data_port = 0;
  /// When a re-creation was asked for (0: none in flight). One whose answer
  /// never came (a Janus that died on it) is asked again after a while.
  std::chrono::steady_clock::time_point recreating{};
};

/// A mountpoint being destroyed, asked again every check until Janus says
/// it is gone: one whose create got no answer (Janus frozen or slow past
/// the timeout: Janus may make it still, so it goes once Janus twice says
/// it has none), one whose session ended, or one that the ledger of an
/// earlier run lists (mountpoint_ledger.hpp).
struct StrayMountpoint {
  enum class Origin { unanswered, ended, leftover };
  Mountpoint m;
  Origin origin = Origin::unanswered;
  int asked = 0, absent = 0;
  int checks = 0;  ///< checks passed since the first minute's asks
  /// The destroy on its way (0: none). An answer to an earlier one (sent
  /// before the stray was kept again) is not this stray's.
  std::uint64_t asking = 0;
};

/// Answers POST /api/v1/sessions with "mode": "broadcast" (the request was
/// checked and admitted): creates the mountpoint, then the session, and
/// answers once Janus has (the message is paused meanwhile).
void create_broadcast(ServerState& s, SoupServerMessage* msg, std::shared_ptr<const GalleryEntry> entry,
                      const std::string& codec, const std::string& address);

/// Answers POST /api/v1/sessions/{id}/viewers (the holder's token checked).
void broadcast_viewers(ServerState& s, SoupServerMessage* msg, Session& session);

/// The session `id` ended: its mountpoint, if any, goes.
void end_broadcast(ServerState& s, const std::string& id);

/// The server stops: every mountpoint goes now (waiting for Janus's answers,
/// briefly), so that none outlives causticd in a Janus that keeps running.
void end_all_broadcasts(ServerState& s);

/// The server starts with broadcasts: each mountpoint that the ledger in
/// the state folder lists (left by a run killed before it destroyed them)
/// becomes a stray, destroyed by check_broadcasts. A damaged ledger is
/// logged and ignored.
void destroy_leftover_mountpoints(ServerState& s);

/// Asks Janus for each mountpoint; one it lost (a restart) is created again
/// on the same ports, so the running pipeline needs no change. Asks Janus
/// to destroy each stray: every check for a minute, then every 10 s while
/// Janus does not answer (it stays listed until Janus has).
void check_broadcasts(ServerState& s);

}  // namespace caustic::server
