// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/image.hpp"

namespace caustic {

HdrImage luminance(const RgbHdrImage& image) {
  HdrImage out{image.width, image.height, std::vector<float>(image.pixels.size() / 3)};
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    const float* p = &image.pixels[3 * i];
    out.pixels[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
  }
  return out;
}

HdrImage channel(const RgbHdrImage& image, int c) {
  HdrImage out{image.width, image.height, std::vector<float>(image.pixels.size() / 3)};
  for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = image.pixels[3 * i + c];
  return out;
}

void set_channel(RgbHdrImage& image, int c, const HdrImage& grey) {
  if (image.width != grey.width || image.height != grey.height || image.pixels.size() != 3 * grey.pixels.size())
    image = RgbHdrImage{grey.width, grey.height, std::vector<float>(3 * grey.pixels.size())};
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) image.pixels[3 * i + c] = grey.pixels[i];
}

}  // namespace caustic
