// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/scene_warnings.hpp"

#include "caustic/receivers.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace caustic {
namespace {

constexpr int kGrid = 9;

struct Traced {
  int ahead = 0;    // rays that meet the screen plane in front of them
  int on_screen = 0;
};

// The light's direction where it meets the object at `at`.
glm::dvec3 arriving(const Scene& scene, const glm::dvec3& at) {
  return scene.light.type == LightType::point ? glm::normalize(at - scene.light.position) : scene.light.direction;
}

// The far face's outward normal: the flat face's opposite, tilted.
glm::dvec3 tilted(const glm::dvec3& flat_normal, const glm::dvec3& u, const glm::dvec3& v, double tu, double tv) {
  return glm::normalize(-flat_normal + tu * glm::normalize(u) + tv * glm::normalize(v));
}

// A ray's direction after the proxy: a mirror reflects it off its far face
// (the flat one when untilted); glass refracts it into the flat face and out
// of the far one (Snell, at the d line's index). Zero when it is reflected
// inside.
glm::dvec3 leave_proxy(const Scene& scene, const glm::dvec3& flat_normal, const glm::dvec3& far_normal,
                       glm::dvec3 dir) {
  const auto facing = [&](const glm::dvec3& n) { return glm::dot(dir, n) < 0 ? n : -n; };
  if (scene.object.material == Material::reflective) return glm::reflect(dir, facing(-far_normal));
  const double n = scene.object.ior;
  dir = glm::refract(dir, facing(flat_normal), 1 / n);
  if (dir == glm::dvec3(0)) return dir;
  return glm::refract(dir, facing(far_normal), n);
}

// The proxy's rays from corner a of its flat face over the face a + u (b - a)
// + v (d - a), leaving by a far face of outward normal `far_normal`.
Traced trace_face(const Scene& scene, const Placement& p, const glm::dvec3& a, const glm::dvec3& b,
                  const glm::dvec3& d, const glm::dvec3& far_normal);

// The proxy's flat face: the face of the bounding box that lies in the flat
// plane (its four corners), sampled on a grid. The far face is flat too:
// the flat slab (parallel faces, which leave the direction as it was), or
// with `steered` the wedge, of those the box holds, that puts the most light
// on the screen. A freeform face steers its light on the whole as a wedge
// of its mean slope does, and that slope is at most the box's thickness
// across its width: a prism's light lands where its slab's would not.
Traced trace_proxy(const Scene& scene, const Placement& p, bool steered = false) {
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
  double low = std::numeric_limits<double>::max(), high = -low;
  for (const auto& corner : p.box) {
    low = std::min(low, glm::dot(corner, p.flat_normal));
    high = std::max(high, glm::dot(corner, p.flat_normal));
  }
  const double max_u = (high - low) / glm::length(b - a), max_v = (high - low) / glm::length(d - a);
  // The flat slab, a coarse fan of wedges, and the wedge that aims the face's
  // centre at the screen's (its far face's normal from Snell's law solved
  // for it: along n d_in - d_out for glass, d_out - d_in for a mirror),
  // within the box's slopes.
  std::vector<glm::dvec2> tilts{{0, 0}};
  if (steered) {
    for (int iu = -2; iu <= 2; ++iu)
      for (int iv = -2; iv <= 2; ++iv) tilts.push_back({max_u * iu / 2, max_v * iv / 2});
    const glm::dvec3 centre = 0.5 * (b + d);
    const glm::dvec3 in = arriving(scene, centre);
    const bool mirror = scene.object.material == Material::reflective;
    const glm::dvec3 inside = mirror ? in : glm::refract(in, glm::dot(in, p.flat_normal) < 0 ? p.flat_normal
                                                                                          : -p.flat_normal,
                                                       1 / scene.object.ior);
    const glm::dvec3 out = glm::normalize(scene.screen.center - centre);
    glm::dvec3 normal = mirror ? out - inside : scene.object.ior * inside - out;
    const double along = glm::dot(normal, -p.flat_normal);
    if (inside != glm::dvec3(0) && std::abs(along) > 1e-9) {
      normal /= along;
      tilts.push_back({std::clamp(glm::dot(normal, glm::normalize(b - a)), -max_u, max_u),
                       std::clamp(glm::dot(normal, glm::normalize(d - a)), -max_v, max_v)});
    }
  }
  Traced best;
  for (const auto& t : tilts) {
    const Traced traced = trace_face(scene, p, a, b, d, tilted(p.flat_normal, b - a, d - a, t.x, t.y));
    if (std::tie(traced.on_screen, traced.ahead) > std::tie(best.on_screen, best.ahead)) best = traced;
  }
  return best;
}

Traced trace_face(const Scene& scene, const Placement& p, const glm::dvec3& a, const glm::dvec3& b,
                  const glm::dvec3& d, const glm::dvec3& far_normal) {
  const glm::dvec3 right = screen_right(scene.screen);
  Traced t;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u = (i + 0.5) / kGrid, v = (j + 0.5) / kGrid;
      const glm::dvec3 at = a + u * (b - a) + v * (d - a);
      const glm::dvec3 dir = leave_proxy(scene, p.flat_normal, far_normal, arriving(scene, at));
      if (dir == glm::dvec3(0)) continue;  // reflected inside the wedge
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
  const Traced t = trace_proxy(scene, placement, true);
  const bool mirror = scene.object.material == Material::reflective;
  // A point light is aimed by where it stands, and ignores light.direction.
  const bool point = scene.light.type == LightType::point;
  const char* aim = point ? "light.position" : "light.direction";
  std::vector<SceneWarning> out;
  if (t.ahead == 0) {
    out.push_back({mirror ? "object.material" : aim,
                   mirror ? "no light reaches the screen: the mirror sends it away from the screen; turn the light or "
                            "the object, or place the screen on the reflection's side (screen.center, screen.normal)"
                   : point ? "no light reaches the screen: the light travels away from it; place the light on the "
                             "object's other side from the screen"
                           : "no light reaches the screen: the light travels away from it; point the light towards "
                             "the screen"});
  } else if (t.on_screen == 0) {
    out.push_back({"screen.center", "no light lands on the screen rectangle: it passes beside it; move the screen "
                                    "or make it larger (screen.width, screen.height), or turn the light back"});
  } else if (t.on_screen * 10 < kGrid * kGrid) {
    out.push_back({aim, "little light lands on the screen (about " +
                                          std::to_string(100 * t.on_screen / (kGrid * kGrid)) +
                                          "% of the object's outline); much of the picture is off the screen"});
  }
  return out;
}

}  // namespace caustic
