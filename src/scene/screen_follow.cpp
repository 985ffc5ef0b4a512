// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/screen_follow.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace caustic {

std::optional<glm::dvec3> light_footprint(const Scene& scene, const Placement& placement) {
  // The middle of the flat face: where the light enters the slab or leaves the mirror.
  const glm::dvec3 from = onto_flat_face(placement, placement.center);
  glm::dvec3 dir = scene.light.type == LightType::point ? from - scene.light.position : scene.light.direction;
  if (!(glm::length(dir) > 0)) return std::nullopt;
  dir = glm::normalize(dir);
  if (scene.object.material == Material::reflective) dir = glm::reflect(dir, placement.flat_normal);
  const ScreenParams& screen = scene.screen;
  const double denom = glm::dot(dir, screen.normal);
  if (std::abs(denom) < 1e-9) return std::nullopt;
  const double s = glm::dot(screen.center - from, screen.normal) / denom;
  if (!(s > 0)) return std::nullopt;
  return from + s * dir;
}

Scene follow_light(Scene scene, const Placement& placement) {
  if (!scene.screen.follow_light) return scene;
  const auto hit = light_footprint(scene, placement);
  if (!hit) return scene;
  ScreenParams& screen = scene.screen;
  // The object's foot on the plane: the shift is measured from there.
  // From the flat face's middle, as the light is followed: the vertices'
  // middle below it is hidden, and would show in a clamped shift.
  const glm::dvec3 middle = onto_flat_face(placement, placement.center);
  const glm::dvec3 foot = middle - glm::dot(middle - screen.center, screen.normal) * screen.normal;
  glm::dvec3 shift = *hit - foot;
  const double limit = kMaxFollow * std::max(screen.width, screen.height);
  if (const double length = glm::length(shift); length > limit) shift *= limit / length;
  const glm::dvec3 center = foot + shift;
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(center[i]) <= kMaxCoordinate)) return scene;
  screen.center = center;
  return scene;
}

std::optional<glm::dvec3> reflected_screen_normal(const ObjectParams& object, const LightParams& light) {
  if (object.material != Material::reflective) return std::nullopt;
  const glm::dvec3 n = glm::normalize(euler_xyz_degrees(object.rotation_deg) * object.flat_face_normal);
  glm::dvec3 d = light.type == LightType::point ? object.position - light.position : light.direction;
  if (!(glm::length(d) > 0)) return std::nullopt;
  const glm::dvec3 r = glm::reflect(glm::normalize(d), n);
  if (!(glm::dot(r, n) > 1e-6)) return std::nullopt;
  return -r;
}

std::vector<std::pair<std::string, std::string>> follow_overrides(const nlohmann::json& written, const Scene& scene) {
  if (!scene.screen.follow_light || !written.is_object()) return {};
  const auto screen = written.find("screen");
  if (screen == written.end() || !screen->is_object()) return {};
  const auto center = screen->find("center");
  if (center == screen->end() || !center->is_array() || center->size() != 3) return {};
  // Overridden only where following moved it visibly (a thousandth of the
  // screen): a centre on the footprint, as a designed scene writes it, is
  // used as written.
  glm::dvec3 written_at;
  for (int i = 0; i < 3; ++i) {
    if (!(*center)[i].is_number()) return {};
    written_at[i] = (*center)[i].get<double>();
  }
  if (glm::length(written_at - scene.screen.center) <= 1e-3 * std::max(scene.screen.width, scene.screen.height))
    return {};
  return {{"screen.center",
           "screen.center sets only the screen plane while screen.follow_light is true: the rectangle slides in the "
           "plane to stay on the light's footprint; set screen.follow_light to false to place it yourself"}};
}

}  // namespace caustic
