// SPDX-License-Identifier: LGPL-2.1-or-later
// Post-processing on the CPU: the twin of post_pass.cpp's
// meter, bright pass, blur and global tone map (shaders/meter.frag,
// bright.frag, blur.frag, tonemap.frag) for a frame whose caustic the CPU
// already deposited (coverage.hpp). Under a software renderer each of those
// full-size passes cost about 5 ms whatever it computed; here the picture is
// one pass over the pixels, the glow a pass over a quarter or less of them,
// and the 8-bit level comes from 255 thresholds on the exposed value
// instead of an exp() and a pow() per pixel. The I420 picture then needs no
// GL at all: a grey frame's Y plane is a table of its 256 levels and its
// chroma is 128. A colour frame (a spectral one) is three such planes,
// each glowing and tone-mapped alone as the shaders do per channel.
#pragma once

#include "caustic/exposure.hpp"
#include "caustic/receivers.hpp"
#include "glow.hpp"
#include "caustic/scene.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace caustic {

class CpuPost {
 public:
  /// What PostPass::prepare meters for the global operator: the histogram
  /// of the luminance of every meter_stride-th pixel of the `width` x
  /// `height` image `hdr` (rows from the bottom, GL's order) of `channels`
  /// floats a pixel: 1 (grey) or 4 (linear RGB and an unused fourth).
  static exposure::Histogram meter(const std::vector<float>& hdr, int width, int height, int channels = 1);

  /// Bloom (when post.bloom_strength and bloom_radius are above 0) and the
  /// global tone map of `hdr` (`width` x `height`, bottom row first,
  /// `channels` as meter() takes them) into an `out_width` x `out_height`
  /// 8-bit picture, grey or RGB, upsampled bilinearly when smaller (a
  /// preview), as PostPass::run draws it.
  /// `tiles`: the atlas's (atlas_layout()), whose edges the glow stops at
  /// (glow.hpp); none, the whole picture.
  void run(const PostParams& post, const std::vector<float>& hdr, int width, int height, int out_width,
           int out_height, double exposure, int channels = 1, const std::vector<AtlasTile>& tiles = {});

  /// The last picture, rows from the bottom, one byte a pixel: one plane,
  /// or R, G and B one after the other for a colour frame.
  const std::vector<std::uint8_t>& picture() const { return picture_; }
  int width() const { return out_width_; }
  int height() const { return out_height_; }
  bool colour() const { return colour_; }

  /// The picture as RGBA (A = 255), rows from the top.
  std::vector<std::uint8_t> rgba() const;
  /// The picture as I420 (BT.601, limited range, planes packed, chroma the
  /// mean of each 2 x 2 block as shaders/i420.frag takes it), rows from the top.
  std::vector<std::uint8_t> i420() const;

 private:
  void glow(const PostParams& post, const std::vector<float>& hdr, int width, int height);
  // One plane of `hdr` into `out` (out_width_ x out_height_ bytes).
  void map_plane(const PostParams& post, const std::vector<float>& hdr, int width, int height, double exposure,
                 std::uint8_t* out);
  // Levels 1..255 start at thresholds_[1..255] of the exposed value (256 and 257 infinite);
  // first_[1 + bucket] is the level at the bottom of a bucket of values that share their
  // float's top 18 bits, first_[0] that of values below them (for levels_gamma_).
  void make_levels(double gamma);
  // The levels of scale * value[0 .. n) into out (levels() steps on from the bucket's first until it holds).
  void levels(const float* value, float scale, int n, std::uint8_t* out) const;

  std::vector<float> glow_, scratch_;
  std::vector<AtlasTile> tiles_;
  GlowCuts cuts_;
  int glow_width_ = 0, glow_height_ = 0;
  std::array<float, 258> thresholds_{};
  std::vector<std::uint8_t> first_;
  double levels_gamma_ = 0;
  std::vector<std::uint8_t> picture_;
  std::vector<float> plane_;  // a colour frame's channel, apart
  int out_width_ = 0, out_height_ = 0;
  bool colour_ = false;
};

}  // namespace caustic
