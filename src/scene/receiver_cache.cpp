// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/receiver_cache.hpp"

#include <algorithm>
#include <list>
#include <mutex>

namespace caustic {
namespace {

// Entries kept: a scene lists at most kMaxReceivers, so a few scenes' worth.
constexpr std::size_t kKept = 32;

struct Entry {
  std::vector<glm::dvec2> profile;  // a lathe's; empty for a shape
  int segments = 0;
  std::weak_ptr<const ReceiverMeshTable> table;  // a shape's
  std::string name;
  glm::dvec3 center, normal, up;
  std::shared_ptr<const ReceiverMesh> mesh;
};

std::mutex lock;
std::list<Entry> kept;  // the most recently used first

template <typename Same, typename Make>
std::shared_ptr<const ReceiverMesh> cached(Same same, Make make) {
  {
    std::lock_guard hold(lock);
    const auto it = std::find_if(kept.begin(), kept.end(), same);
    if (it != kept.end()) {
      kept.splice(kept.begin(), kept, it);
      return it->mesh;
    }
  }
  Entry made = make();  // outside the lock: seconds for a large shape, and other threads' lookups go on
  std::lock_guard hold(lock);
  kept.push_front(std::move(made));
  if (kept.size() > kKept) kept.pop_back();
  return kept.front().mesh;
}

}  // namespace

std::shared_ptr<const ReceiverMesh> lathe_mesh(const std::vector<glm::dvec2>& profile, int segments,
                                               const glm::dvec3& base, const glm::dvec3& normal, const glm::dvec3& up) {
  return cached(
      [&](const Entry& e) {
        return !e.profile.empty() && e.segments == segments && e.center == base && e.normal == normal && e.up == up &&
               e.profile == profile;
      },
      [&] {
        return Entry{profile, segments, {}, "", base, normal, up,
                     std::make_shared<const ReceiverMesh>(make_lathe(profile, segments, base, normal, up))};
      });
}

std::shared_ptr<const ReceiverMesh> shape_mesh(const std::shared_ptr<const ReceiverMeshTable>& table,
                                               const std::string& name, const glm::dvec3& center,
                                               const glm::dvec3& normal, const glm::dvec3& up) {
  return cached(
      [&](const Entry& e) {
        return e.profile.empty() && e.table.lock() == table && e.name == name && e.center == center &&
               e.normal == normal && e.up == up;
      },
      [&] {
        return Entry{{}, 0, table, name, center, normal, up,
                     std::make_shared<const ReceiverMesh>(place_receiver_mesh(table->meshes.at(name), center, normal, up))};
      });
}

}  // namespace caustic
