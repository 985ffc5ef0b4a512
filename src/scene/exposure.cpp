// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/exposure.hpp"

#include <algorithm>
#include <cmath>

namespace caustic::exposure {

void count(Histogram& histogram, float value) {
  if (!(value > std::exp2(kLog2Lit))) return;  // NaN too
  const int bin = static_cast<int>((std::log2(value) - kLog2Lit) * kBinsPerStop);
  ++histogram[std::clamp(bin, 0, kBins - 1)];
}

Histogram histogram(const HdrImage& image) {
  Histogram h{};
  const int k = meter_stride(image.width, image.height);
  for (int y = image.height - 1; y >= 0; y -= k)
    for (int x = 0; x < image.width; x += k) count(h, image.at(x, y));
  return h;
}

double quantile(const Histogram& histogram, double q) {
  std::uint64_t lit = 0;
  for (const auto n : histogram) lit += n;
  if (lit == 0) return 0;
  const double rank = std::clamp(q, 0.0, 1.0) * static_cast<double>(lit);
  double below = 0;
  for (int b = 0; b < kBins; ++b) {
    const double n = histogram[b];
    if (n > 0 && below + n >= rank) {
      const double within = std::clamp((rank - below) / n, 0.0, 1.0);
      return std::exp2(kLog2Lit + (b + within) / kBinsPerStop);
    }
    below += n;
  }
  return std::exp2(kLog2Lit + kBins / kBinsPerStop);
}

double exposure_for(double value, double gamma) {
  if (!(value > 0)) return 1.0;
  const double knee = -std::log(1.0 - std::pow(kMeteredLevel, gamma));
  return std::clamp(knee / value, 1e-6, 1e6);
}

double adapt(double shown, double target, double dt, double tau) {
  if (!(shown > 0) || tau <= 0 || std::abs(std::log(target / shown)) < 0.01) return target;
  const double step = 1.0 - std::exp(-std::max(dt, 0.0) / tau);
  const double next = shown * std::exp(step * std::log(target / shown));
  return std::abs(std::log(target / next)) < 0.01 ? target : next;
}

double settled_exposure(const PostParams& post, const HdrImage& image) {
  if (post.exposure_mode == ExposureMode::manual) return post.exposure;
  const double metered = quantile(histogram(image), post.auto_percentile);
  return (metered > 0 ? exposure_for(metered, post.gamma) : 1.0) * post.exposure;
}

}  // namespace caustic::exposure
