// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/param_store.hpp"

namespace caustic {

ParamStore::ParamStore(Scene initial, std::function<void(const Scene&)> check, std::function<Scene(Scene)> resolve)
    : origin_(initial), check_(std::move(check)), resolve_(std::move(resolve)) {
  validate_scene(initial);
  scene_ = admit(std::move(initial));
}

Scene ParamStore::admit(Scene candidate) const {
  if (resolve_) candidate = resolve_(std::move(candidate));
  if (check_) check_(candidate);
  return candidate;
}

ParamStore::Snapshot ParamStore::snapshot() const {
  std::lock_guard lock(mutex_);
  return {scene_, version_.load(std::memory_order_relaxed), published_, previous_};
}

void ParamStore::publish(Scene next) {
  scene_ = std::move(next);
  previous_ = published_;
  published_ = std::chrono::steady_clock::now();
}

std::uint64_t ParamStore::apply_patch(const nlohmann::json& patch) {
  std::lock_guard lock(mutex_);
  publish(admit(apply_merge_patch(scene_, patch, &origin_)));
  return version_.fetch_add(1, std::memory_order_acq_rel) + 1;
}

std::uint64_t ParamStore::replace(const Scene& scene) {
  validate_scene(scene);
  Scene next = admit(scene);
  std::lock_guard lock(mutex_);
  publish(std::move(next));
  return version_.fetch_add(1, std::memory_order_acq_rel) + 1;
}

}  // namespace caustic
