// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/design_target.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace caustic::design {
namespace {

// The sRGB decoding curve (IEC 61966-2-1), input and output in [0, 1].
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

bool is_float_format(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::HALF ||
         t.basetype == OIIO::TypeDesc::DOUBLE;
}

// Integer pictures are display-referred (sRGB) unless their metadata says
// linear; float pictures are scene-referred (linear) unless it says sRGB.
bool encoded_srgb(const OIIO::ImageSpec& spec) {
  std::string cs = spec.get_string_attribute("oiio:ColorSpace");
  std::transform(cs.begin(), cs.end(), cs.begin(), [](unsigned char c) { return std::tolower(c); });
  if (cs.find("linear") != std::string::npos) return false;
  if (cs.find("srgb") != std::string::npos) return true;
  return !is_float_format(spec.format);
}

// Exact overlap weights of n output cells over `in` input samples along one axis.
struct Span {
  int first = 0;
  std::vector<double> weights;
};
std::vector<Span> box_spans(int offset, int in, int n) {
  std::vector<Span> spans(n);
  const double scale = static_cast<double>(in) / n;
  for (int o = 0; o < n; ++o) {
    const double a = o * scale, b = (o + 1) * scale;
    Span& s = spans[o];
    s.first = offset + static_cast<int>(std::floor(a));
    for (int p = static_cast<int>(std::floor(a)); p < in && p < b; ++p) {
      const double w = std::min(b, p + 1.0) - std::max(a, static_cast<double>(p));
      s.weights.push_back(std::max(w, 0.0) / scale);
    }
  }
  return spans;
}

}  // namespace

RgbHdrImage load_target_rgb(const std::filesystem::path& file) {
  const std::string name = file.string();
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw TargetError(name + ": cannot read the picture (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw TargetError(name + ": the picture is empty");
  if (spec.width > kMaxTargetSide || spec.height > kMaxTargetSide ||
      static_cast<long long>(spec.width) * spec.height > kMaxTargetPixels)
    throw TargetError(name + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                      " pixels is too large (at most " + std::to_string(kMaxTargetSide) + " per side and " +
                      std::to_string(kMaxTargetPixels) + " in all)");
  const int channels = spec.nchannels;
  std::vector<float> raw(static_cast<std::size_t>(spec.width) * spec.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data()))
    throw TargetError(name + ": cannot decode the picture (" + in->geterror() + ")");
  const bool srgb = encoded_srgb(spec);
  // Colour: the first three channels are R, G, B; grey (1 or 2 channels): the first.
  const bool colour = channels >= 3;
  const std::size_t count = static_cast<std::size_t>(spec.width) * spec.height;
  RgbHdrImage out{spec.width, spec.height, std::vector<float>(3 * count)};
  for (std::size_t p = 0; p < count; ++p) {
    const float* c = &raw[p * channels];
    double rgb[3] = {c[0], colour ? c[1] : c[0], colour ? c[2] : c[0]};
    for (double& v : rgb) {
      if (!std::isfinite(v)) throw TargetError(name + ": the picture holds NaN or infinite values");
      v = std::max(v, 0.0);
      if (srgb) v = srgb_to_linear(std::min(v, 1.0));
    }
    for (int k = 0; k < 3; ++k) out.pixels[3 * p + k] = static_cast<float>(rgb[k]);
  }
  return out;
}

Image load_target(const std::filesystem::path& file) { return luminance(load_target_rgb(file)); }

Image box_resample_square(const Image& image, int n) {
  const int side = std::min(image.width, image.height);
  const auto xs = box_spans((image.width - side) / 2, side, n);
  const auto ys = box_spans((image.height - side) / 2, side, n);
  // Separable: rows first into a side x n buffer, then columns.
  std::vector<double> rows(static_cast<std::size_t>(image.height) * n, 0.0);
  for (int y = 0; y < image.height; ++y)
    for (int o = 0; o < n; ++o) {
      double s = 0;
      for (std::size_t k = 0; k < xs[o].weights.size(); ++k) s += xs[o].weights[k] * image.at(xs[o].first + k, y);
      rows[static_cast<std::size_t>(y) * n + o] = s;
    }
  Image out{n, n, std::vector<float>(static_cast<std::size_t>(n) * n)};
  for (int o = 0; o < n; ++o)
    for (int x = 0; x < n; ++x) {
      double s = 0;
      for (std::size_t k = 0; k < ys[o].weights.size(); ++k)
        s += ys[o].weights[k] * rows[static_cast<std::size_t>(ys[o].first + k) * n + x];
      out.pixels[static_cast<std::size_t>(o) * n + x] = static_cast<float>(s);
    }
  return out;
}

}  // namespace caustic::design
