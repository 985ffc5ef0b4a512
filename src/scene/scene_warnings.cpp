// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/scene_warnings.hpp"

#include "caustic/receivers.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace caustic {
namespace {

constexpr int kGrid = 9;

struct Traced {
  int ahead = 0;    // rays that meet the screen plane in front of them
  int on_screen = 0;
};

// The proxy's flat face: the face of the bounding box that lies in the flat
// plane (its four corners), sampled on a grid.
Traced trace_proxy(const Scene& scene, const Placement& p) {
  std::vector<glm::dvec3> flat;
  for (const auto& corner : p.box)
    if (std::abs(glm::dot(corner, p.flat_normal) - p.flat_offset) < 1e-6 * (1 + std::abs(p.flat_offset)))
      flat.push_back(corner);
  if (flat.size() != 4) flat.assign(p.box.begin(), p.box.begin() + 4);
  // Sorted by distance from the first corner: its two neighbours, then the
  // opposite corner; the face is a + u (b - a) + v (d - a).
  std::sort(flat.begin() + 1, flat.end(), [&](const glm::dvec3& x, const glm::dvec3& y) {
    return glm::length(x - flat[0]) < glm::length(y - flat[0]);
  });
  const glm::dvec3 a = flat[0], b = flat[1], d = flat[2];
  const glm::dvec3 right = screen_right(scene.screen);
  Traced t;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u = (i + 0.5) / kGrid, v = (j + 0.5) / kGrid;
      const glm::dvec3 at = a + u * (b - a) + v * (d - a);
      glm::dvec3 dir = scene.light.type == LightType::point ? glm::normalize(at - scene.light.position)
                                                            : scene.light.direction;
      // A flat slab leaves the direction as it was; a flat mirror reflects it.
      if (scene.object.material == Material::reflective) dir = glm::reflect(dir, p.flat_normal);
      const double denom = glm::dot(dir, scene.screen.normal);
      if (std::abs(denom) < 1e-9) continue;
      const double s = glm::dot(scene.screen.center - at, scene.screen.normal) / denom;
      if (!(s > 0)) continue;
      ++t.ahead;
      const glm::dvec3 hit = at + s * dir - scene.screen.center;
      if (std::abs(glm::dot(hit, right)) <= 0.5 * scene.screen.width &&
          std::abs(glm::dot(hit, scene.screen.up)) <= 0.5 * scene.screen.height)
        ++t.on_screen;
    }
  return t;
}

}  // namespace

double proxy_share_on_screen(const Scene& scene, const Placement& placement) {
  return static_cast<double>(trace_proxy(scene, placement).on_screen) / (kGrid * kGrid);
}

std::vector<SceneWarning> light_warnings(const Scene& scene, const Placement& placement) {
  const Traced t = trace_proxy(scene, placement);
  const bool mirror = scene.object.material == Material::reflective;
  std::vector<SceneWarning> out;
  if (t.ahead == 0) {
    out.push_back({mirror ? "object.material" : "light.direction",
                   mirror ? "no light reaches the screen: the mirror sends it away from the screen; turn the light or "
                            "the object, or place the screen on the reflection's side (screen.center, screen.normal)"
                          : "no light reaches the screen: the light travels away from it; point the light towards "
                            "the screen"});
  } else if (t.on_screen == 0) {
    out.push_back({"screen.center", "no light lands on the screen rectangle: it passes beside it; move the screen "
                                    "or make it larger (screen.width, screen.height), or turn the light back"});
  } else if (t.on_screen * 10 < kGrid * kGrid) {
    out.push_back({"light.direction", "little light lands on the screen (about " +
                                          std::to_string(100 * t.on_screen / (kGrid * kGrid)) +
                                          "% of the object's outline); much of the picture is off the screen"});
  }
  return out;
}

}  // namespace caustic
