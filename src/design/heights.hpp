// SPDX-License-Identifier: LGPL-2.1-or-later
// From a lens-to-screen correspondence to the heights of the freeform face:
// paraxial heights in closed form from the transport potential, then exact
// Snell slopes integrated by least squares (DCT solve), repeated until the
// heights settle. Millimetres; the face is z = h(x, y), glass above it, the
// light going -z inside the glass, the screen the plane z = -focus.
#pragma once

#include "caustic/design.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace caustic::design {

/// Paraxial heights in closed form (no solve). With X the lens point,
/// x the screen point (unit square) and psi the transport potential averaged
/// around the vertex, h = k (|X - x|^2 / 2 + psi), k = W^2 / (f (n - 1)):
/// the Legendre conjugate of |x|^2 / 2 + psi, whose gradient k (X - x) is
/// the thin-prism slope that sends X to x. Zero mean.
std::vector<double> paraxial_heights(const std::vector<glm::dvec2>& lens_unit, const std::vector<glm::dvec2>& screen_unit,
                                     const std::vector<double>& psi_at_vertices, double size, double focus, double ior);

/// Exact slopes: the ray leaving (lens, height) toward its screen point t
/// (unit) needs a normal parallel to n d - t (vector Snell, d = -z), i.e.
/// slope G = -t_xy / (n + t_z). A deviation beyond 90 deg - critical angle
/// would need total internal reflection: it is capped just below that and
/// the vertex counted in grid.tir.
void exact_slopes(FaceGrid& grid, double focus, double ior);

/// Least-squares heights from the slopes over the grid edges:
/// min sum (h_w - h_v - (G_v + G_w)/2 . (p_w - p_v))^2. The normal equations
/// are the grid graph Laplacian (Neumann), diagonal in the DCT-II basis of
/// size w. Zero mean.
std::vector<double> integrate_slopes(const FaceGrid& grid);

/// What the exact-Snell passes did: how many ran, and the largest height
/// change of the last (settled: below the tolerance, not cut off by the cap).
struct SnellPasses {
  int passes = 0;
  double last_change = 0;  ///< mm
  bool settled = false;
};

/// Exact slopes and integration repeated until no height moves more than
/// `tolerance` mm (at most `max_passes`).
SnellPasses refine_heights(FaceGrid& grid, double focus, double ior, double tolerance, int max_passes);

}  // namespace caustic::design
