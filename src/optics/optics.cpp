// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/optics.hpp"

#include <cmath>

namespace caustic::optics {

std::optional<Vec3> point_light_entry(const Vec3& light, const Vec3& v, const Plane& plane, double n) {
  const double h_light = plane.signed_distance(light);
  const double h_v = -plane.signed_distance(v);
  if (!(h_light > 0.0) || !(h_v > 0.0)) return std::nullopt;
  const Vec3 foot_light = light - h_light * plane.normal;
  const Vec3 foot_v = v + h_v * plane.normal;
  const Vec3 across = foot_v - foot_light;
  const double d = glm::length(across);
  // Straight below the light every ray enters at the foot: no plane of incidence.
  if (d <= 1e-12 * (h_light + h_v)) return foot_light;
  const Vec3 dir = across / d;
  // f(x) = sin(theta_i) - n sin(theta_t) rises monotonically from f(0) < 0 to f(d) > 0.
  auto f = [&](double x) {
    return x / std::hypot(x, h_light) - n * (d - x) / std::hypot(d - x, h_v);
  };
  double lo = 0.0, hi = d;
  for (int iter = 0; iter < 80 && hi - lo > 1e-15 * d; ++iter) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0.0 ? lo : hi) = mid;
  }
  return foot_light + 0.5 * (lo + hi) * dir;
}

double solid_angle(const Vec3& eye, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ra = a - eye, rb = b - eye, rc = c - eye;
  const double la = glm::length(ra), lb = glm::length(rb), lc = glm::length(rc);
  // Triple product through edge vectors: far from the triangle the vectors to
  // its corners are nearly parallel and b x c alone loses precision.
  const double triple = glm::dot(ra, glm::cross(rb - ra, rc - ra));
  const double denom = la * lb * lc + glm::dot(ra, rb) * lc + glm::dot(ra, rc) * lb + glm::dot(rb, rc) * la;
  return std::abs(2.0 * std::atan2(triple, denom));
}

}  // namespace caustic::optics
