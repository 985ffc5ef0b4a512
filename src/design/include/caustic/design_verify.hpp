// SPDX-License-Identifier: LGPL-2.1-or-later
// Checking a design the way a user would see it: the scene that renders it,
// and the engine's (or the reference tracer's) caustic against the target.
#pragma once

#include "caustic/design.hpp"
#include "caustic/scene.hpp"

#include <cstdint>
#include <filesystem>

namespace caustic::design {

/// The scene that shows the design: the face mesh `mesh_file` (as written in
/// the JSON, relative to the scene's folder), flat face at the design's
/// flat_offset, directional light straight down, the screen (W x W, facing
/// up) at z = -focus, fidelity "manual" at the mesh as designed, Fresnel on,
/// `pixels` per side, exposure chosen for the target.
Scene design_scene(const Design& design, const std::string& mesh_file, int pixels);

/// Tone-map exposure that puts the target's 99th-percentile irradiance at
/// 90% of white (1 - exp(-e E) = 0.9), within [0.01, 10].
double target_exposure(const HdrImage& target);

struct Verification {
  double seconds = 0;
  double ssim = 0;            ///< tone-mapped (docs/accuracy.md), 8x8 windows
  double relative_l1 = 0;     ///< sum |render - target| / sum target
  double leak = 0;            ///< share of the light that lands on black-floor cells
  double ideal_leak = 0;      ///< the same share in the target itself (the floor's light)
  double landed = 0;          ///< flux on the screen / flux into the lens
  HdrImage render;            ///< relative irradiance, design.n pixels per side
};

/// Compares a relative-irradiance image (design.n x design.n) with the
/// target, both box-filtered by `factor` first (which must divide design.n).
Verification compare_with_target(const Design& design, const HdrImage& render, double exposure, int factor = 1);

/// Renders the design with the engine (Fresnel off, so the target's mean of
/// 1 is what should land) and compares; a tinted face (a colour design)
/// by its brightest channel, what its shape was designed for. Needs a
/// current GL 4.5 context.
Verification verify_with_engine(const Design& design);

/// The same with the independent photon tracer (`photons` photons),
/// compared on a grid of about 128 x 128 (box filter) where photon noise is small.
Verification verify_with_reference(const Design& design, std::uint64_t photons);

}  // namespace caustic::design
