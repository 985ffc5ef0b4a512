// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/image_compare.hpp"

#include <cmath>
#include <stdexcept>

namespace caustic {

HdrImage box_down(const HdrImage& image, int factor) {
  if (factor < 1 || image.width % factor || image.height % factor)
    throw std::invalid_argument("box_down: factor " + std::to_string(factor) + " does not divide " +
                                std::to_string(image.width) + "x" + std::to_string(image.height));
  const int w = image.width / factor, h = image.height / factor;
  HdrImage out{w, h, std::vector<float>(static_cast<std::size_t>(w) * h, 0.0f)};
  const float weight = 1.0f / static_cast<float>(factor * factor);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      out.pixels[static_cast<std::size_t>(y / factor) * w + x / factor] += image.at(x, y) * weight;
  return out;
}

namespace {

std::vector<double> tonemap(const HdrImage& image, double exposure, double gamma) {
  std::vector<double> out(image.pixels.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = std::pow(1.0 - std::exp(-exposure * std::max(0.0f, image.pixels[i])), 1.0 / gamma);
  return out;
}

}  // namespace

double tonemapped_ssim(const HdrImage& a, const HdrImage& b, double exposure, double gamma) {
  if (a.width != b.width || a.height != b.height) throw std::invalid_argument("tonemapped_ssim: sizes differ");
  const std::vector<double> x = tonemap(a, exposure, gamma), y = tonemap(b, exposure, gamma);
  constexpr int window = 8, stride = 4;
  constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double sum = 0;
  int count = 0;
  for (int y0 = 0; y0 + window <= a.height; y0 += stride)
    for (int x0 = 0; x0 + window <= a.width; x0 += stride) {
      double mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0;
      for (int j = y0; j < y0 + window; ++j)
        for (int i = x0; i < x0 + window; ++i) {
          const std::size_t k = static_cast<std::size_t>(j) * a.width + i;
          mx += x[k], my += y[k];
          sxx += x[k] * x[k], syy += y[k] * y[k], sxy += x[k] * y[k];
        }
      const double n = window * window;
      mx /= n, my /= n;
      const double vx = sxx / n - mx * mx, vy = syy / n - my * my, cov = sxy / n - mx * my;
      sum += (2 * mx * my + c1) * (2 * cov + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++count;
    }
  if (count == 0) throw std::invalid_argument("tonemapped_ssim: images smaller than one 8x8 window");
  return sum / count;
}

ImageError compare(const HdrImage& image, const HdrImage& reference, double exposure, double gamma) {
  if (image.width != reference.width || image.height != reference.height)
    throw std::invalid_argument("compare: image sizes differ");
  double diff = 0, sum = 0, sq = 0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const double d = static_cast<double>(image.pixels[i]) - reference.pixels[i];
    diff += std::abs(d);
    sum += std::abs(reference.pixels[i]);
    sq += d * d;
  }
  if (!(sum > 0)) throw std::invalid_argument("compare: the reference image is black");
  const double n = static_cast<double>(image.pixels.size());
  ImageError e;
  e.relative_l1 = diff / sum;
  e.relative_rmse = std::sqrt(sq / n) / (sum / n);
  e.ssim = tonemapped_ssim(image, reference, exposure, gamma);
  return e;
}

}  // namespace caustic
