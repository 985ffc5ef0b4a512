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

}  // namespace caustic
