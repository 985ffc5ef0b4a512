// SPDX-License-Identifier: LGPL-2.1-or-later
// The engine's picture of a scene against the photon reference's, as the
// receivers' tests (floor and wall, lathe, mesh shape) hold them: 16 M
// photons, the relative L1 printed under `what` for the log to show it.
#pragma once

#include "caustic/reference.hpp"
#include "gl_test_support.hpp"

#include <cstdio>

namespace caustic::testing {

inline double reference_l1(const Scene& scene, const Mesh& mesh, const HdrImage& engine, const char* what) {
  ReferenceOptions options;
  options.photons = 16'000'000;
  const double l1 = relative_l1(engine, trace_reference(scene, mesh, options).image);
  std::printf("%s: relative L1 engine vs reference %.4f\n", what, l1);
  return l1;
}

}  // namespace caustic::testing
