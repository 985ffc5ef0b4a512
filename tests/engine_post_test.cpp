// SPDX-License-Identifier: LGPL-2.1-or-later
// Post-processing against its definition (docs/scene-format.md, "post"):
// the picture is 255 (1 - exp(-exposure (E + strength B)))^(1/gamma) with
// B the Gaussian (sigma = bloom_radius output pixels, normalised) of the
// excess max(E - threshold, 0). The oracle convolves the engine's own HDR
// image on the CPU at full resolution; the engine computes the glow on a
// smaller image, so the comparison bounds what that costs.
#include "gl_test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace caustic;
using namespace caustic::testing;

namespace {

// Separable discrete Gaussian, kernel to 4 sigma, zero outside the image
// (the test keeps the light far from the edges).
std::vector<double> gaussian_bloom(const HdrImage& hdr, double threshold, double sigma) {
  const int w = hdr.width, h = hdr.height, r = static_cast<int>(std::ceil(4 * sigma));
  std::vector<double> kernel(2 * r + 1);
  double total = 0;
  for (int k = -r; k <= r; ++k) total += kernel[k + r] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& k : kernel) k /= total;
  std::vector<double> excess(hdr.pixels.size()), rows(hdr.pixels.size()), out(hdr.pixels.size());
  for (std::size_t i = 0; i < excess.size(); ++i) excess[i] = std::max(hdr.pixels[i] - threshold, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = -r; k <= r; ++k)
        if (x + k >= 0 && x + k < w) rows[y * w + x] += kernel[k + r] * excess[y * w + x + k];
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = -r; k <= r; ++k)
        if (y + k >= 0 && y + k < h) out[y * w + x] += kernel[k + r] * rows[(y + k) * w + x];
  return out;
}

class Bloom : public GlTest, public ::testing::WithParamInterface<double> {};

}  // namespace

TEST_P(Bloom, IsTheGaussianOfTheExcessAboveTheThreshold) {
  // A 20 x 20 pixel square of relative irradiance 1 in a 256^2 picture.
  const auto mesh = shared(grid_mesh(flat_face(2.0), 8, 8));
  Scene s = straight_down_scene(3.0, 50.0, 51.2, 256);
  s.post.exposure = 2.0;
  s.post.gamma = 1.0;
  s.post.bloom_threshold = 0.25;
  s.post.bloom_strength = 2.0;
  s.post.bloom_radius = GetParam();
  const HdrImage hdr = render(s, mesh);
  const Rgba8Image ldr = engine_->read_ldr();
  const std::vector<double> bloom = gaussian_bloom(hdr, s.post.bloom_threshold, s.post.bloom_radius);
  double worst = 0, peak = 0;
  int compared = 0;
  for (int y = 0; y < hdr.height; ++y)
    for (int x = 0; x < hdr.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * hdr.width + x;
      const double expected =
          255.0 * (1.0 - std::exp(-s.post.exposure * (hdr.pixels[i] + s.post.bloom_strength * bloom[i])));
      // Only where the glow matters: a tenth of its peak's worth or more.
      if (s.post.bloom_strength * bloom[i] * s.post.exposure * 255.0 < 4.0) continue;
      worst = std::max(worst, std::abs(ldr.pixels[i * 4] - expected));
      peak = std::max(peak, expected);
      ++compared;
    }
  std::printf("bloom radius %.0f px: %d pixels compared, worst difference %.2f of 255 (brightest %.0f)\n",
              s.post.bloom_radius, compared, worst, peak);
  EXPECT_GT(compared, 400);
  EXPECT_LE(worst, 6.0);
}

// 4 px: glow at half resolution; 10 px: quarter; 20 px: eighth.
INSTANTIATE_TEST_SUITE_P(Radii, Bloom, ::testing::Values(4.0, 10.0, 20.0));
