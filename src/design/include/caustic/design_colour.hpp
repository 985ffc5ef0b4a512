// SPDX-License-Identifier: LGPL-2.1-or-later
// Colour targets with one tinted face (report 3.6, docs/design.md "Colour").
// One freeform face sends each part of the light to one place; a tint on the
// face (Mesh::colours) then decides that light's colour. So the face is
// designed for the brightest channel of the target, M = max(R, G, B), and
// each vertex is tinted with the target's colour where its ray lands divided
// by M there: the screen receives M * (R, G, B) / M = (R, G, B), with no
// second surface to align. The price is light: a tint passes only what its
// colour keeps, so a saturated target shows dimmer than a grey one.
#pragma once

#include "caustic/design.hpp"
#include "caustic/design_verify.hpp"

namespace caustic::design {

/// The target's brightest channel per pixel: what the face must deliver.
Image brightest_channel(const RgbHdrImage& target);

/// Centre square crop and box filter onto n x n cells, channel by channel
/// (box_resample_square).
RgbHdrImage box_resample_square(const RgbHdrImage& image, int n);

/// Sets design.face.colours: each vertex gets the target's colour (design.n
/// cells per side) where its ray must land, divided by the brightest
/// channel there, both interpolated bilinearly between cells: the cells
/// around a vertex mix their colours in proportion to the light each
/// receives. Where that light is below the black floor the vertex stays
/// clear (white): it carries the floor's faint glow only.
void tint_face(Design& design, const RgbHdrImage& target);

struct ColourVerification {
  Verification brightest;          ///< the render's brightest channel against the design's target
  double relative_l1[3] = {0, 0, 0};  ///< per channel, against the target's colour at the design's scale
  /// Mean distance in CIE 1931 (x, y) between render and target, weighted by
  /// the target's luminance, over cells at least a tenth of the mean bright.
  double chromaticity_error = 0;
  RgbHdrImage render;              ///< relative irradiance, design.n pixels per side
  RgbHdrImage aim;                 ///< what should land: the target's colour at the design's scale
};

/// Renders the tinted design with the engine (Fresnel off) and compares it
/// with `target` channel by channel. Needs a current GL 4.5 context.
ColourVerification verify_colour_with_engine(const Design& design, const RgbHdrImage& target);

}  // namespace caustic::design
