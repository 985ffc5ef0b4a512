// SPDX-License-Identifier: LGPL-2.1-or-later
// The small pools the water's engine tests build: a surface of still level
// z = 0 over a floor, in millimetres, lit by the sun from one side.
#pragma once

#include "gl_test_support.hpp"

#include <cmath>

namespace caustic::testing {

inline constexpr double kWater = 1.333;
inline constexpr double kHalf = 10.0;  // the water's footprint, mm

// Unpolarised Fresnel transmittance from air into a medium of index `n` at
// incidence cos_i: 1 - (r_s^2 + r_p^2) / 2 (Hecht, Optics, eq. 4.42-4.43),
// written out here so that the oracles share no code with the engine's.
inline double transmittance(double cos_i, double n) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

// A pool: the surface (mesh z = -h, turned over so that world z = h) at
// z = 0, the floor `depth` below it, 256 px across `floor_size` mm, the sun
// `theta` from the vertical travelling towards +x.
inline Scene water_pool(double depth, double theta, double floor_size) {
  Scene s = straight_down_scene(0.0, depth, floor_size, 256);
  s.object.flat_face_offset.reset();
  s.object.shape = Shape::surface;
  s.object.ior = kWater;
  s.object.rotation_deg = {180, 0, 0};
  s.light.direction = {std::sin(theta), 0, -std::cos(theta)};
  s.render.fresnel = true;
  return s;
}

}  // namespace caustic::testing
