// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/receiver_cache.hpp"

#include <algorithm>
#include <list>
#include <mutex>
#include <vector>

namespace caustic {
namespace {

// Meshes kept though no scene holds them: a scene lists at most
// kMaxReceivers, so a few scenes' worth (a patch that drops a receiver and
// the next that brings it back build it once).
constexpr std::size_t kKept = 32;

struct Entry {
  std::vector<glm::dvec2> profile;  // a lathe's; empty for a shape
  int segments = 0;
  std::weak_ptr<const ReceiverMeshTable> table;  // a shape's
  std::string name;
  glm::dvec3 center, normal, up;
  // Weak: an entry lives as long as its mesh does, in a scene or in
  // `recent`. A cache of the last few alone was missed by every patch once
  // the sessions held more than that many receivers between them, each
  // patch building them all again on the main loop.
  std::weak_ptr<const ReceiverMesh> mesh;
};

std::mutex lock;
std::vector<Entry> known;  // every mesh still held somewhere
std::list<std::shared_ptr<const ReceiverMesh>> recent;  // the last kKept used, the most recent first

// Under the lock: `mesh` first among the recent ones, the oldest let go.
void touch(const std::shared_ptr<const ReceiverMesh>& mesh) {
  recent.remove(mesh);
  recent.push_front(mesh);
  if (recent.size() > kKept) recent.pop_back();
}

template <typename Same, typename Make>
std::shared_ptr<const ReceiverMesh> cached(Same same, Make make) {
  {
    std::lock_guard hold(lock);
    std::erase_if(known, [](const Entry& e) { return e.mesh.expired(); });
    for (const Entry& e : known)
      if (std::shared_ptr<const ReceiverMesh> mesh = e.mesh.lock(); mesh && same(e)) {
        touch(mesh);
        return mesh;
      }
  }
  // Outside the lock: seconds for a large shape, and other threads' lookups go on.
  std::shared_ptr<const ReceiverMesh> mesh;
  Entry made = make(mesh);
  std::lock_guard hold(lock);
  made.mesh = mesh;
  known.push_back(std::move(made));
  touch(mesh);
  return mesh;
}

}  // namespace

std::shared_ptr<const ReceiverMesh> lathe_mesh(const std::vector<glm::dvec2>& profile, int segments,
                                               const glm::dvec3& base, const glm::dvec3& normal, const glm::dvec3& up) {
  return cached(
      [&](const Entry& e) {
        return !e.profile.empty() && e.segments == segments && e.center == base && e.normal == normal && e.up == up &&
               e.profile == profile;
      },
      [&](std::shared_ptr<const ReceiverMesh>& mesh) {
        mesh = std::make_shared<const ReceiverMesh>(make_lathe(profile, segments, base, normal, up));
        return Entry{profile, segments, {}, "", base, normal, up, {}};
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
      [&](std::shared_ptr<const ReceiverMesh>& mesh) {
        mesh = std::make_shared<const ReceiverMesh>(place_receiver_mesh(table->meshes.at(name), center, normal, up));
        return Entry{{}, 0, table, name, center, normal, up, {}};
      });
}

}  // namespace caustic
