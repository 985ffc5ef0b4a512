#include "caustic/param_store.hpp"

namespace caustic {

ParamStore::ParamStore(Scene initial, std::function<void(const Scene&)> check)
    : scene_(std::move(initial)), check_(std::move(check)) {
  validate_scene(scene_);
  if (check_) check_(scene_);
}

ParamStore::Snapshot ParamStore::snapshot() const {
  std::lock_guard lock(mutex_);
  return {scene_, version_.load(std::memory_order_relaxed)};
}

std::uint64_t ParamStore::apply_patch(const nlohmann::json& patch) {
  std::lock_guard lock(mutex_);
  Scene next = apply_merge_patch(scene_, patch);
  if (check_) check_(next);
  scene_ = std::move(next);
  return version_.fetch_add(1, std::memory_order_acq_rel) + 1;
}

std::uint64_t ParamStore::replace(const Scene& scene) {
  validate_scene(scene);
  if (check_) check_(scene);
  std::lock_guard lock(mutex_);
  scene_ = scene;
  return version_.fetch_add(1, std::memory_order_acq_rel) + 1;
}

}  // namespace caustic
