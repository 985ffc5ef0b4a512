// SPDX-License-Identifier: LGPL-2.1-or-later
// Grid optimal transport (G. Nader and G. Guennebaud, "Instant Transport Maps
// on 2D Grids", ACM TOG 37(6), 2018), written from the paper: the uniform
// light on the lens is carried onto the target masses of the n x n screen
// cells. Unit square coordinates on both sides.
//
// The unknown is a potential psi on the screen cells; screen vertex v (the
// regular grid point x_v = (i, j) / n) comes from the lens point
// X_v = x_v + grad_v psi, grad_v being the centred difference of the four
// cells around v (psi mirrored across the border, so border points slide
// along the border and corners stay). Cell c then receives the light of the
// lens quad of its four X_v: the residual is r_c = area(X-quad c) - m_c.
#pragma once

#include "caustic/design.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace caustic::design {

struct TransportOptions {
  int steps = 6;             ///< homotopy m^t, t = 1/steps ... 1
  double tolerance = 1e-4;   ///< final sum |r|
  /// Intermediate homotopy steps stop earlier: they only warm-start the next
  /// one. Measured: 3e-3 instead of 1e-3 cut a 512^2 logo from 492 to 200
  /// iterations with the same final residual (1.1e-3).
  double step_tolerance = 3e-3;
  int max_iterations = 400;  ///< per step
  int stall_window = 20;     ///< a step stops when `stall_window` iterations
  double stall_gain = 0.1;   ///< cut the residual by less than this fraction
};

struct TransportResult {
  std::vector<double> psi;        ///< n x n, row j along +y
  std::vector<glm::dvec2> lens;   ///< (n+1)^2 lens points X_v, unit square
  double residual = 0;            ///< sum |r| at the end
  int iterations = 0;
};

/// Solves for the map. `mass`: n x n positive cell masses summing to 1.
/// `progress` (optional) is called about every iteration with the
/// step, iteration count and residual (seconds left 0: the caller adds them).
TransportResult solve_transport(int n, const std::vector<double>& mass, const TransportOptions& options,
                                const ProgressFn& progress = {});

/// Lens points X_v = x_v + grad_v psi of a potential; (n+1)^2 values.
std::vector<glm::dvec2> lens_points(int n, const std::vector<double>& psi);

/// Signed areas of the n x n lens quads (counter-clockwise positive).
std::vector<double> quad_areas(int n, const std::vector<glm::dvec2>& lens);

/// Mean of psi over the (up to four, mirrored at the border) cells around each vertex.
std::vector<double> vertex_mean(int n, const std::vector<double>& psi);

}  // namespace caustic::design
