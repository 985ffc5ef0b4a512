// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/receivers.hpp"

#include <cmath>
#include <limits>

namespace caustic {

std::vector<AtlasTile> atlas_layout(int width, int height, std::size_t count) {
  if (count <= 1) return {AtlasTile{0, 0, width, height}};
  const auto columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const auto rows = static_cast<int>((count + static_cast<std::size_t>(columns) - 1) / static_cast<std::size_t>(columns));
  const int w = width / columns, h = height / rows;
  std::vector<AtlasTile> tiles;
  for (std::size_t i = 0; i < count; ++i)
    tiles.push_back({static_cast<int>(i % static_cast<std::size_t>(columns)) * w,
                     static_cast<int>(i / static_cast<std::size_t>(columns)) * h, w, h});
  return tiles;
}

glm::dvec3 screen_right(const ScreenParams& screen) { return glm::normalize(glm::cross(screen.up, screen.normal)); }

std::vector<ScreenParams> receiving_surfaces(const Scene& scene) {
  std::vector<ScreenParams> all{scene.screen};
  all.insert(all.end(), scene.receivers.begin(), scene.receivers.end());
  return all;
}

bool has_shaped_receiver(const Scene& scene) {
  for (const ScreenParams& r : scene.receivers)
    if (r.body()) return true;
  return false;
}

ReceiverHit first_receiver(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& dir) {
  ReceiverHit best;
  best.distance = std::numeric_limits<double>::infinity();
  const bool bounded = !scene.receivers.empty();
  // Called for every ray and photon: the surfaces are read in place, not gathered.
  for (std::size_t i = 0; i <= scene.receivers.size(); ++i) {
    const ScreenParams& r = i == 0 ? scene.screen : scene.receivers[i - 1];
    if (const ReceiverMesh* body = r.body()) {
      if (const auto hit = body->intersect(origin, dir, best.distance))
        best = {static_cast<int>(i), hit->uv - 0.5, hit->distance, hit->element};
      continue;
    }
    const double denom = glm::dot(dir, r.normal);
    // Grazing below 1e-6, as caustic.vert and the CPU model (vertex_rays) say:
    // one rule, so the GL's and the CPU's set-ups drop and count alike.
    if (!(std::abs(denom) > 1e-6)) continue;
    const double s = glm::dot(r.center - origin, r.normal) / denom;
    if (!(s > 0) || !(s < best.distance)) continue;
    const glm::dvec3 p = origin + s * dir - r.center;
    const glm::dvec3 right = screen_right(r);
    const glm::dvec2 local(glm::dot(p, right), glm::dot(p, r.up));
    if (bounded && (std::abs(local.x) > 0.5 * r.width || std::abs(local.y) > 0.5 * r.height)) continue;
    best = {static_cast<int>(i), local, s};
  }
  return best;
}

}  // namespace caustic
