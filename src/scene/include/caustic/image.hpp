// SPDX-License-Identifier: LGPL-2.1-or-later
// The two picture types every layer exchanges. They live below the engine so
// that the reference tracer, image files and the designer use them without
// linking OpenGL.
#pragma once

#include <cstdint>
#include <vector>

namespace caustic {

/// Relative irradiance, one float per pixel, row 0 at the top of the screen.
struct HdrImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Linear RGB relative irradiance (sRGB primaries), three floats per pixel
/// in R, G, B order, row 0 at the top.
struct RgbHdrImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
};

/// The luminance (Rec. 709 weights) of each pixel: R = G = B = v gives v.
HdrImage luminance(const RgbHdrImage& image);

/// Channel `c` (0 R, 1 G, 2 B) as a grey image, and back: what per-channel
/// filters and comparisons are built from.
HdrImage channel(const RgbHdrImage& image, int c);
/// Writes `grey` into channel `c` of `image`, which takes its size (and is
/// allocated, black, when its size differs).
void set_channel(RgbHdrImage& image, int c, const HdrImage& grey);

/// Tone-mapped 8-bit RGBA, row 0 at the top.
struct Rgba8Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

}  // namespace caustic
