// SPDX-License-Identifier: LGPL-2.1-or-later
// One design as DesignJobs keeps it, shared by the files that run designs
// (design_jobs.cpp) and read them back from their folders at a start
// (design_restore.cpp).
#pragma once

#include "design_jobs.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace caustic::server {

inline std::int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// In a design's folder: the owner deleted it while a worker still ran it.
/// The worker throws the folder away when it ends; a start that finds the
/// mark (the server stopped first) does so instead of designing it again.
inline constexpr const char* kRemovedMark = "removed";

/// A failed design is kept this long at the most (or design_expiry_s when
/// shorter): long enough for its uploader to read why, not a week of a
/// place among design_max_stored.
inline constexpr std::int64_t kFailedKeptS = 3600;

struct DesignJobs::Job {
  enum class State { restoring, queued, designing, ready, failed };
  /// The state's name in the API. A switch, not a table indexed by the
  /// enum: a state added above is a compiler warning, not a wrong name.
  static const char* state_name(State s) {
    switch (s) {
      case State::restoring: return "restoring";
      case State::queued: return "queued";
      case State::designing: return "designing";
      case State::ready: return "ready";
      case State::failed: return "failed";
    }
    return "failed";
  }
  std::string id, token, name, extension;
  bool colour = false;  ///< designed in colour (a tinted face)
  std::int64_t created = 0;
  std::filesystem::path folder;
  State state = State::queued;
  double progress = 0;
  std::string stage, error;
  nlohmann::json report;  ///< the public figures only
  // Ready: what answers need without the scene in memory, and the scene
  // while a session or the recent list holds it.
  std::vector<unsigned char> thumbnail;
  nlohmann::json info;
  std::weak_ptr<const GalleryEntry> held;
  bool loading = false;  ///< queued to be read back from its folder
};

}  // namespace caustic::server
