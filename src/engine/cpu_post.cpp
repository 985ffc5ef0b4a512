// SPDX-License-Identifier: LGPL-2.1-or-later
#include "cpu_post.hpp"

#include "bands.hpp"
#include "glow.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace caustic {
namespace {

constexpr int kMinBandRows = 64;    // rows a thread at the least (bands.hpp)

// Buckets of the level table: the exposed value's float bits above kDropBits,
// from 2^-40 to 2^24. A bucket spans 2^-9 (0.2%) of its value, less than
// two levels' thresholds lie apart for the gammas in use, so a value's level
// is nearly always its bucket's first or the next (levels() steps on until
// it holds, whatever the gamma).
constexpr int kDropBits = 14;
constexpr std::uint32_t kFirstKey = (127u - 40u) << (23 - kDropBits);
constexpr std::uint32_t kEndKey = (127u + 24u) << (23 - kDropBits);

// Bilinear sampling of a `from`-texel axis onto `to` pixels as GL's texture()
// with clamp to edge: pixel i's centre falls at texel (i + 0.5) from/to - 0.5.
struct Tap {
  int lo, hi;
  float t;  // weight of hi
};
std::vector<Tap> taps(int from, int to) {
  std::vector<Tap> out(static_cast<std::size_t>(to));
  for (int i = 0; i < to; ++i) {
    const double s = (i + 0.5) * from / to - 0.5;
    const int lo = static_cast<int>(std::floor(s));
    out[i] = {std::clamp(lo, 0, from - 1), std::clamp(lo + 1, 0, from - 1), static_cast<float>(s - lo)};
  }
  return out;
}

// The glow's taps of each output pixel kept within the tile of the picture's
// pixel under it (`cuts` in glow texels, glow.hpp), as tonemap.frag clamps
// its glow coordinate: no tile shows its neighbour's glow.
void confine(std::vector<Tap>& glow_taps, const std::vector<int>& cuts, int pixels, int shrink) {
  const int out = static_cast<int>(glow_taps.size());
  for (int i = 0; i < out; ++i) {
    const int pixel = std::min(static_cast<int>((i + 0.5) * pixels / out), pixels - 1);
    const auto [first, end] = glow_segment(cuts, std::min(pixel / shrink, cuts.back() - 1));
    glow_taps[i].lo = std::clamp(glow_taps[i].lo, first, end - 1);
    glow_taps[i].hi = std::clamp(glow_taps[i].hi, first, end - 1);
  }
}

// One row of a bilinearly sampled image: rows a and b mixed by t into
// `mixed` (a whole row at once, which vectorises), then taps across.
void sample_row(const float* a, const float* b, float t, const std::vector<Tap>& across, std::vector<float>& mixed,
                float* out) {
  for (std::size_t x = 0; x < mixed.size(); ++x) mixed[x] = a[x] + t * (b[x] - a[x]);
  for (std::size_t x = 0; x < across.size(); ++x) {
    const Tap& c = across[x];
    const float lo = mixed[c.lo], hi = mixed[c.hi];
    out[x] = lo + c.t * (hi - lo);
  }
}

}  // namespace

exposure::Histogram CpuPost::meter(const std::vector<float>& hdr, int width, int height, int channels) {
  exposure::Histogram histogram{};
  const int k = exposure::meter_stride(width, height);
  for (int y = 0; y < height; y += k)
    for (int x = 0; x < width; x += k) {
      const float* p = &hdr[(static_cast<std::size_t>(y) * width + x) * channels];
      // shaders/local.glsl's luminance(), in the same float arithmetic.
      exposure::count(histogram, channels == 1 ? p[0] : 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2]);
    }
  return histogram;
}

void CpuPost::glow(const PostParams& post, const std::vector<float>& hdr, int width, int height) {
  // The sizes and weights of PostPass::run, so that both draw one glow.
  const int shrink = glow_shrink(post.bloom_radius);
  const int bw = std::max(1, width / shrink), bh = std::max(1, height / shrink);
  glow_width_ = bw;
  glow_height_ = bh;
  glow_.resize(static_cast<std::size_t>(bw) * bh);
  scratch_.resize(glow_.size());
  const float threshold = static_cast<float>(post.bloom_threshold), mean = 1.0f / static_cast<float>(shrink * shrink);
  // Each small texel the mean of its shrink x shrink pixels above the
  // threshold: the rows summed first (whole rows, vectorised), then each
  // run of shrink sums. Only an image narrower than shrink clamps.
  in_bands(bh, kMinBandRows / shrink, [&](int lo, int hi) {
    std::vector<float> sums(static_cast<std::size_t>(std::max(width, bw * shrink)));
    for (int by = lo; by < hi; ++by) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int dy = 0; dy < shrink; ++dy) {
        const float* row = &hdr[static_cast<std::size_t>(std::min(by * shrink + dy, height - 1)) * width];
        for (int x = 0; x < width; ++x) sums[x] += std::max(row[x] - threshold, 0.0f);
      }
      for (int x = width; x < bw * shrink; ++x) sums[x] = sums[width - 1];
      float* out = &glow_[static_cast<std::size_t>(by) * bw];
      for (int bx = 0; bx < bw; ++bx) {
        float sum = 0.0f;
        for (int dx = 0; dx < shrink; ++dx) sum += sums[bx * shrink + dx];
        out[bx] = sum * mean;
      }
    }
  });

  const std::vector<double> exact = glow_weights(post.bloom_radius, shrink);
  const int radius = static_cast<int>(exact.size()) - 1;
  std::vector<float> weight(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k) weight[k + radius] = static_cast<float>(exact[std::abs(k)]);

  // Across (into scratch_), each tile's run of a row padded with its edge
  // texels as the clamp to edge reads them (glow.hpp's cuts); then down
  // (back into glow_), row by row, so that both directions are sums of
  // whole rows the compiler can vectorise.
  cuts_ = glow_cuts(tiles_, height, shrink, bw, bh);
  in_bands(bh, kMinBandRows / shrink, [&](int lo, int hi) {
    std::vector<float> padded;
    for (int by = lo; by < hi; ++by) {
      for (std::size_t c = 0; c + 1 < cuts_.x.size(); ++c) {
        const int a = cuts_.x[c], n = cuts_.x[c + 1] - a;
        const float* row = &glow_[static_cast<std::size_t>(by) * bw + a];
        padded.resize(static_cast<std::size_t>(n + 2 * radius));
        std::fill_n(padded.begin(), radius, row[0]);
        std::copy_n(row, n, padded.begin() + radius);
        std::fill_n(padded.begin() + radius + n, radius, row[n - 1]);
        float* out = &scratch_[static_cast<std::size_t>(by) * bw + a];
        std::fill(out, out + n, 0.0f);
        for (int k = 0; k <= 2 * radius; ++k) {
          const float w = weight[k];
          const float* in = padded.data() + k;
          for (int bx = 0; bx < n; ++bx) out[bx] += w * in[bx];
        }
      }
    }
  });
  in_bands(bh, kMinBandRows / shrink, [&](int lo, int hi) {
    for (int by = lo; by < hi; ++by) {
      float* out = &glow_[static_cast<std::size_t>(by) * bw];
      std::fill(out, out + bw, 0.0f);
      const auto [first, end] = glow_segment(cuts_.y, by);
      for (int k = -radius; k <= radius; ++k) {
        const float w = weight[k + radius];
        const float* in = &scratch_[static_cast<std::size_t>(std::clamp(by + k, first, end - 1)) * bw];
        for (int bx = 0; bx < bw; ++bx) out[bx] += w * in[bx];
      }
    }
  });
}

void CpuPost::make_levels(double gamma) {
  // Level k (of 255) is written once the curve reaches (k - 0.5) / 255, as a
  // unorm target rounds: (1 - exp(-x))^(1/gamma) >= c at x >= -ln(1 - c^gamma).
  if (gamma == levels_gamma_ && !first_.empty()) return;
  levels_gamma_ = gamma;
  thresholds_[0] = 0.0f;
  for (int k = 1; k <= 255; ++k)
    thresholds_[k] = std::max(static_cast<float>(-std::log1p(-std::pow((k - 0.5) / 255.0, gamma))),
                              std::numeric_limits<float>::denorm_min());  // 0 stays level 0
  thresholds_[256] = thresholds_[257] = INFINITY;
  // Entry 0 stands for every value below 2^-40 (0 too), level 0 on.
  first_.assign(kEndKey - kFirstKey + 1, 0);
  int level = 0;
  for (std::uint32_t key = kFirstKey; key < kEndKey; ++key) {
    const float bottom = std::bit_cast<float>(key << kDropBits);
    while (level < 255 && bottom >= thresholds_[level + 1]) ++level;
    first_[key - kFirstKey + 1] = static_cast<std::uint8_t>(level);
  }
}

void CpuPost::levels(const float* value, float scale, int n, std::uint8_t* out) const {
  // Without branches on the data (a caustic's pixels cross thresholds at
  // random): the bucket's first level, one comparison on, and the rare value
  // that needs more steps (or lies below 2^-40) finished by the loop.
  const std::uint8_t* first = first_.data();
  const float* thresholds = thresholds_.data();
  for (int i = 0; i < n; ++i) {
    const float x = std::max(0.0f, scale * value[i]);  // NaN too
    const std::uint32_t key = std::clamp(std::bit_cast<std::uint32_t>(x) >> kDropBits, kFirstKey - 1, kEndKey - 1);
    int k = first[key - (kFirstKey - 1)];
    // x >= the next threshold as the sign of their difference (exact in
    // sign, and +0 when equal): a comparison the compiler would branch on.
    k = std::min(k + 1 - static_cast<int>(std::bit_cast<std::uint32_t>(x - thresholds[k + 1]) >> 31), 255);
    if (k < 255 && x >= thresholds[k + 1]) [[unlikely]]
      while (k < 255 && x >= thresholds[k + 1]) ++k;
    out[i] = static_cast<std::uint8_t>(k);
  }
}

void CpuPost::run(const PostParams& post, const std::vector<float>& hdr, int width, int height, int out_width,
                  int out_height, double exposure, int channels, const std::vector<AtlasTile>& tiles) {
  tiles_ = tiles;
  out_width_ = out_width;
  out_height_ = out_height;
  colour_ = channels != 1;
  const std::size_t plane = static_cast<std::size_t>(out_width) * out_height;
  picture_.resize(colour_ ? 3 * plane : plane);
  make_levels(post.gamma);
  if (!colour_) return map_plane(post, hdr, width, height, exposure, picture_.data());
  // A channel at a time, apart: the grey path's whole-row loops, three times.
  plane_.resize(static_cast<std::size_t>(width) * height);
  for (int c = 0; c < 3; ++c) {
    in_bands(height, kMinBandRows, [&](int lo, int hi) {
      for (std::size_t i = static_cast<std::size_t>(lo) * width; i < static_cast<std::size_t>(hi) * width; ++i)
        plane_[i] = hdr[i * channels + c];
    });
    map_plane(post, plane_, width, height, exposure, &picture_[c * plane]);
  }
}

void CpuPost::map_plane(const PostParams& post, const std::vector<float>& hdr, int width, int height,
                        double exposure, std::uint8_t* picture) {
  const int out_width = out_width_, out_height = out_height_;
  const bool bloom = post.bloom_strength > 0 && post.bloom_radius > 0;
  if (bloom) glow(post, hdr, width, height);
  const bool same = width == out_width && height == out_height;
  const auto across = taps(width, out_width), down = taps(height, out_height);
  // The glow's taps only with a glow: without one its size is 0 (or a
  // previous frame's), and taps() of 0 texels would clamp to [0, -1].
  std::vector<Tap> glow_across, glow_down;
  if (bloom) {
    glow_across = taps(glow_width_, out_width);
    glow_down = taps(glow_height_, out_height);
    const int shrink = glow_shrink(post.bloom_radius);
    confine(glow_across, cuts_.x, width, shrink);
    confine(glow_down, cuts_.y, height, shrink);
  }
  const float strength = bloom ? static_cast<float>(post.bloom_strength) : 0.0f, scale = static_cast<float>(exposure);
  in_bands(out_height, kMinBandRows, [&](int lo, int hi) {
    std::vector<float> value(static_cast<std::size_t>(out_width)), extra(value.size());
    std::vector<float> mixed(static_cast<std::size_t>(width)), glow_mixed(static_cast<std::size_t>(glow_width_));
    for (int y = lo; y < hi; ++y) {
      const float* row = value.data();
      if (same) {
        row = &hdr[static_cast<std::size_t>(y) * width];
      } else {
        const Tap& d = down[y];
        sample_row(&hdr[static_cast<std::size_t>(d.lo) * width], &hdr[static_cast<std::size_t>(d.hi) * width], d.t,
                   across, mixed, value.data());
      }
      if (bloom) {
        const Tap& d = glow_down[y];
        sample_row(&glow_[static_cast<std::size_t>(d.lo) * glow_width_],
                   &glow_[static_cast<std::size_t>(d.hi) * glow_width_], d.t, glow_across, glow_mixed, extra.data());
        for (int x = 0; x < out_width; ++x) value[x] = row[x] + strength * extra[x];
        row = value.data();
      }
      levels(row, scale, out_width, &picture[static_cast<std::size_t>(y) * out_width]);
    }
  });
}

std::vector<std::uint8_t> CpuPost::rgba() const {
  const std::size_t plane = static_cast<std::size_t>(out_width_) * out_height_;
  const std::size_t green = colour_ ? plane : 0, blue = colour_ ? 2 * plane : 0;
  std::vector<std::uint8_t> out(plane * 4);
  std::size_t n = 0;
  for (int y = out_height_ - 1; y >= 0; --y)
    for (int x = 0; x < out_width_; ++x, n += 4) {
      const std::size_t i = static_cast<std::size_t>(y) * out_width_ + x;
      out[n] = picture_[i];
      out[n + 1] = picture_[green + i];
      out[n + 2] = picture_[blue + i];
      out[n + 3] = 255;
    }
  return out;
}

std::vector<std::uint8_t> CpuPost::i420() const {
  const std::size_t plane = static_cast<std::size_t>(out_width_) * out_height_;
  std::vector<std::uint8_t> out(plane * 3 / 2, 128);
  if (!colour_) {
    // shaders/i420.frag's Y of an 8-bit grey g: 16 + (0.256788 + 0.504129 + 0.097906) g, rounded as a unorm target.
    std::array<std::uint8_t, 256> luma{};
    for (int g = 0; g < 256; ++g)
      luma[g] = static_cast<std::uint8_t>(std::lround(16.0 + g * (0.256788 + 0.504129 + 0.097906)));
    for (int y = 0; y < out_height_; ++y) {
      const std::uint8_t* row = &picture_[static_cast<std::size_t>(out_height_ - 1 - y) * out_width_];
      std::uint8_t* dest = &out[static_cast<std::size_t>(y) * out_width_];
      for (int x = 0; x < out_width_; ++x) dest[x] = luma[row[x]];
    }
    return out;
  }
  // shaders/i420.frag's sums in float, on levels / 255, rounded as a unorm target.
  const auto rgb = [&](int x, int y) {  // y from the top
    const std::size_t i = static_cast<std::size_t>(out_height_ - 1 - y) * out_width_ + x;
    return glm::vec3(picture_[i], picture_[plane + i], picture_[2 * plane + i]) / 255.0f;
  };
  const auto unorm = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  for (int y = 0; y < out_height_; ++y)
    for (int x = 0; x < out_width_; ++x)
      out[static_cast<std::size_t>(y) * out_width_ + x] =
          unorm(16.0f / 255.0f + glm::dot(rgb(x, y), glm::vec3(0.256788f, 0.504129f, 0.097906f)));
  const int half_w = out_width_ / 2, half_h = out_height_ / 2;
  std::uint8_t* u = &out[plane];
  std::uint8_t* v = u + static_cast<std::size_t>(half_w) * half_h;
  for (int y = 0; y < half_h; ++y)
    for (int x = 0; x < half_w; ++x) {
      const glm::vec3 mean = 0.25f * (rgb(2 * x, 2 * y) + rgb(2 * x + 1, 2 * y) + rgb(2 * x, 2 * y + 1) +
                                      rgb(2 * x + 1, 2 * y + 1));
      const std::size_t k = static_cast<std::size_t>(y) * half_w + x;
      u[k] = unorm(128.0f / 255.0f + glm::dot(mean, glm::vec3(-0.148223f, -0.290993f, 0.439216f)));
      v[k] = unorm(128.0f / 255.0f + glm::dot(mean, glm::vec3(0.439216f, -0.367788f, -0.071427f)));
    }
  return out;
}

}  // namespace caustic
