// SPDX-License-Identifier: LGPL-2.1-or-later
// The live parameters of one session: the only state that the HTTP side and
// a renderer share. Writers replace the whole scene under a mutex and bump a
// version; a renderer compares versions (one atomic load) and copies the
// scene only when it changed.
#pragma once

#include "caustic/scene.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>

namespace caustic {

class ParamStore {
 public:
  struct Snapshot {
    Scene scene;
    std::uint64_t version;
    /// When this version was published: a renderer that notices it late
    /// still knows how long the parameters have been still.
    std::chrono::steady_clock::time_point published;
    /// When the version before it was published (the epoch for the first):
    /// whether a change came alone or amid others, however many versions
    /// a busy renderer skipped.
    std::chrono::steady_clock::time_point previous;
  };

  /// `resolve` turns every candidate scene into the one to render (for
  /// example fidelity "auto" writing its choice in); `check` then runs on it
  /// before it is published (for example geometry checks against the mesh)
  /// and throws SceneError to refuse.
  explicit ParamStore(Scene initial, std::function<void(const Scene&)> check = {},
                      std::function<Scene(Scene)> resolve = {});

  Snapshot snapshot() const;
  std::uint64_t version() const { return version_.load(std::memory_order_acquire); }

  /// Applies an RFC 7396 merge patch, a null restoring the initial scene's
  /// value (origin()); returns the new version. Throws SceneError and leaves
  /// everything unchanged when the result is invalid.
  std::uint64_t apply_patch(const nlohmann::json& patch);

  /// The scene as given to the constructor, before `resolve`.
  const Scene& origin() const { return origin_; }

  /// Replaces the scene; same checks and guarantees as apply_patch.
  std::uint64_t replace(const Scene& scene);

 private:
  mutable std::mutex mutex_;
  const Scene origin_;
  Scene scene_;
  std::chrono::steady_clock::time_point published_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point previous_{};
  void publish(Scene next);  // under mutex_
  std::atomic<std::uint64_t> version_{1};
  std::function<void(const Scene&)> check_;
  std::function<Scene(Scene)> resolve_;
  Scene admit(Scene candidate) const;  // resolve, check
};

}  // namespace caustic
