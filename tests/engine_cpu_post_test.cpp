// SPDX-License-Identifier: LGPL-2.1-or-later
// Post-processing on the CPU (src/engine/cpu_post.hpp).
// Oracles: the tone curve 255 (1 - exp(-exposure E))^(1/gamma), rounded,
// for values spanning twelve decades and gammas across the scene format's
// range; BT.601's limited-range Y of a grey level (16 + 219 g / 255) and
// neutral chroma. The glow is held to its Gaussian by engine_post_test.cpp
// for both paths; here the CPU's picture also matches the GL passes it
// replaces (post_pass.cpp, i420.frag) across bloom sizes, gammas, automatic
// exposure, previews and sizes that the glow's shrink does not divide.
#include "gl_test_support.hpp"

#include "cpu_post.hpp"

#include "caustic/dispersion.hpp"

#include <cmath>
#include <cstdio>

using namespace caustic;
using namespace caustic::testing;

TEST(CpuPostCurve, EveryLevelIsTheRoundedToneCurve) {
  // 8192 values from 1e-30 to 1e3, each a pixel of a 64 x 128 image: at
  // gamma 10 the lowest levels start below the level table's first bucket (2^-40).
  const int side = 64, rows = 128;
  std::vector<float> hdr(side * rows);
  for (std::size_t i = 0; i < hdr.size(); ++i) hdr[i] = static_cast<float>(std::pow(10.0, -30.0 + 33.0 * i / hdr.size()));
  PostParams post;
  post.bloom_strength = 0;
  for (const double gamma : {0.1, 1.0, 2.2, 10.0})
    for (const double exposure : {0.37, 1.0, 25.0}) {
      SCOPED_TRACE("gamma " + std::to_string(gamma) + ", exposure " + std::to_string(exposure));
      post.gamma = gamma;
      CpuPost cpu;
      cpu.run(post, hdr, side, rows, side, rows, exposure);
      int checked = 0, levels_seen = 0, last = -1;
      for (std::size_t i = 0; i < hdr.size(); ++i) {
        const double x = static_cast<double>(static_cast<float>(exposure) * hdr[i]);
        const double exact = 255.0 * std::pow(-std::expm1(-x), 1.0 / gamma);
        // Within float rounding of a half level either way is right.
        if (std::abs(exact - std::floor(exact) - 0.5) < 1e-3) continue;
        ASSERT_EQ(cpu.picture()[i], static_cast<int>(std::lround(exact))) << "value " << hdr[i];
        ++checked;
        if (cpu.picture()[i] != last) ++levels_seen, last = cpu.picture()[i];
      }
      EXPECT_GT(checked, 8000);
      EXPECT_GT(levels_seen, 100);  // the ramp crosses most levels: the table's buckets are exercised
    }
  // A value that is not a number shows black, as max(NaN, 0) does on the GPUs at hand.
  hdr[0] = std::nanf("");
  CpuPost cpu;
  cpu.run(post, hdr, side, rows, side, rows, 1.0);
  EXPECT_EQ(cpu.picture()[0], 0);
}

TEST(CpuPostCurve, I420IsLimitedRangeGreyWithNeutralChroma) {
  const int w = 16, h = 16;  // levels 0..255, one a pixel, bottom row first
  std::vector<float> hdr(w * h);
  PostParams post;
  post.bloom_strength = 0;
  post.gamma = 1.0;
  // E = -ln(1 - (g + 0.1) / 255) maps to g + 0.1 of 255; the last pixel is far past white.
  for (int g = 0; g < 255; ++g) hdr[g] = static_cast<float>(-std::log(1.0 - (g + 0.1) / 255.0));
  hdr[255] = 100.0f;
  CpuPost cpu;
  cpu.run(post, hdr, w, h, w, h, 1.0);
  const auto i420 = cpu.i420();
  ASSERT_EQ(i420.size(), static_cast<std::size_t>(w * h * 3 / 2));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int g = cpu.picture()[(h - 1 - y) * w + x];  // the planes run top-down
      EXPECT_EQ(i420[y * w + x], std::lround(16 + 219.0 * g / 255.0)) << "level " << g;
    }
  for (std::size_t i = w * h; i < i420.size(); ++i) ASSERT_EQ(i420[i], 128);
  const auto rgba = cpu.rgba();
  for (int i = 0; i < w * h; ++i) {
    const int g = cpu.picture()[(h - 1 - i / w) * w + i % w];
    ASSERT_EQ(rgba[4 * i], g);
    ASSERT_EQ(rgba[4 * i + 2], g);
    ASSERT_EQ(rgba[4 * i + 3], 255);
  }
}

TEST(CpuPostCurve, ColourI420IsBt601LimitedRange) {
  // 2 x 2 blocks of black, white, the primaries and the secondaries, each
  // channel far past white or 0; the oracle is BT.601's limited-range
  // matrix (Y 16 + 65.481 R + 128.553 G + 24.966 B for R, G, B in [0, 1]).
  const glm::dvec3 colours[8] = {{0, 0, 0}, {1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  const int w = 16, h = 2;
  std::vector<float> hdr(w * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) hdr[(y * w + x) * 4 + c] = colours[x / 2][c] > 0 ? 100.0f : 0.0f;
  PostParams post;
  post.bloom_strength = 0;
  CpuPost cpu;
  cpu.run(post, hdr, w, h, w, h, 1.0, 4);
  ASSERT_TRUE(cpu.colour());
  const auto i420 = cpu.i420();
  ASSERT_EQ(i420.size(), static_cast<std::size_t>(w * h * 3 / 2));
  for (int b = 0; b < 8; ++b) {
    const glm::dvec3 c = colours[b];
    const double y = 16 + 65.481 * c.r + 128.553 * c.g + 24.966 * c.b;
    const double cb = 128 - 37.797 * c.r - 74.203 * c.g + 112.0 * c.b;
    const double cr = 128 + 112.0 * c.r - 93.786 * c.g - 18.214 * c.b;
    for (int k : {0, 1, w, w + 1}) EXPECT_NEAR(i420[2 * b + k], y, 0.51) << "block " << b;
    EXPECT_NEAR(i420[w * h + b], cb, 0.51) << "block " << b;
    EXPECT_NEAR(i420[w * h + w / 2 + b], cr, 0.51) << "block " << b;
  }
  const auto rgba = cpu.rgba();
  for (int b = 0; b < 8; ++b)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(rgba[8 * b + c], colours[b][c] > 0 ? 255 : 0);
}

namespace {

struct Frame {
  Rgba8Image ldr;
  std::vector<std::uint8_t> i420;
  FrameStats stats;
};

struct Variant {
  const char* name;
  int width, height, divisor;
  void (*adjust)(PostParams&);
};

}  // namespace

class CpuPostAgainstGl : public GlTest {
 protected:
  // A fresh engine each time, so that automatic exposure settles at once.
  Frame draw(const Scene& scene, TriangleSetup setup, int divisor) {
    static const auto lens = shared(grid_mesh(plano_convex_lens(40.0, 10.0), 65, 65));
    engine_ = std::make_unique<Engine>();
    engine_->set_triangle_setup(setup);
    engine_->set_preview_divisor(divisor);
    engine_->set_scene(scene, lens);
    engine_->render();
    Frame f{engine_->read_ldr(), std::vector<std::uint8_t>(engine_->picture_bytes(PixelFormat::i420)),
            engine_->stats()};
    std::uint64_t tag = 0;
    engine_->start_readback(7, PixelFormat::i420);
    EXPECT_TRUE(engine_->poll_readback(f.i420.data(), f.i420.size(), &tag, true));
    EXPECT_EQ(tag, 7u);
    return f;
  }
};

TEST_F(CpuPostAgainstGl, BothDrawTheSamePictureAndStream) {
  const Variant variants[] = {
      {"defaults: gamma 2.2, glow at a quarter, automatic", 256, 256, 1, [](PostParams&) {}},
      {"gamma 1, glow at half, manual", 256, 256, 1,
       [](PostParams& p) {
         p.gamma = 1.0;
         p.exposure_mode = ExposureMode::manual;
         p.exposure = 3.0;
         p.bloom_radius = 4;
         p.bloom_threshold = 0.5;
         p.bloom_strength = 0.5;
       }},
      {"a size the glow's eighth does not divide", 360, 202, 1, [](PostParams& p) { p.bloom_radius = 20; }},
      {"preview at a half", 256, 256, 2, [](PostParams&) {}},
      {"preview at a third of an odd size", 360, 202, 3, [](PostParams& p) { p.gamma = 1.8; }},
  };
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.name);
    // The lens near its focus: a bright fold far above the glow's threshold.
    Scene s = straight_down_scene(4.0, 60.0, 30.0, v.width);
    s.render.fresnel = true;
    s.render.height = v.height;
    s.screen.height = 30.0 * v.height / v.width;
    v.adjust(s.post);
    const Frame gl = draw(s, TriangleSetup::gpu, v.divisor), cpu = draw(s, TriangleSetup::cpu, v.divisor);
    EXPECT_FALSE(gl.stats.cpu_post);
    EXPECT_TRUE(cpu.stats.cpu_post);
    EXPECT_NEAR(cpu.stats.exposure, gl.stats.exposure, 2e-3 * gl.stats.exposure);
    ASSERT_EQ(cpu.ldr.pixels.size(), gl.ldr.pixels.size());
    // The two caustics differ in float rounding (engine_setup_test.cpp): a
    // level where a value straddles a rounding boundary.
    int worst = 0, differ = 0, lit = 0;
    for (std::size_t i = 0; i < gl.ldr.pixels.size(); i += 4) {
      const int d = std::abs(cpu.ldr.pixels[i] - gl.ldr.pixels[i]);
      worst = std::max(worst, d);
      differ += d > 0;
      lit += gl.ldr.pixels[i] > 8;
      ASSERT_EQ(cpu.ldr.pixels[i + 1], cpu.ldr.pixels[i]);
      ASSERT_EQ(cpu.ldr.pixels[i + 3], 255);
    }
    const int pixels = v.width * v.height;
    std::printf("%s: %d of %d pixels differ, by %d at most; %d lit\n", v.name, differ, pixels, worst, lit);
    EXPECT_GT(lit, pixels / 100);
    EXPECT_LE(worst, 2);
    EXPECT_LT(differ, pixels / 50);
    ASSERT_EQ(cpu.i420.size(), gl.i420.size());
    int worst_y = 0;
    for (int i = 0; i < pixels; ++i) worst_y = std::max(worst_y, std::abs(cpu.i420[i] - gl.i420[i]));
    EXPECT_LE(worst_y, 2);
    for (std::size_t i = pixels; i < cpu.i420.size(); ++i) ASSERT_EQ(cpu.i420[i], gl.i420[i]);
  }
}

TEST_F(CpuPostAgainstGl, AColourFrameDrawsTheSamePictureAndStream) {
  // The lens in BK7 at three wavelengths: its focus fringed in colour. Each
  // channel glows and maps alone on both paths; the GL's glow is in half
  // floats, the CPU's in floats.
  for (const int divisor : {1, 2}) {
    SCOPED_TRACE("divisor " + std::to_string(divisor));
    Scene s = straight_down_scene(4.0, 60.0, 30.0, 256);
    s.render.fresnel = true;
    s.render.wavelengths = 3;
    s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
    const Frame gl = draw(s, TriangleSetup::gpu, divisor), cpu = draw(s, TriangleSetup::cpu, divisor);
    EXPECT_TRUE(cpu.stats.colour);
    EXPECT_FALSE(gl.stats.cpu_post);
    EXPECT_TRUE(cpu.stats.cpu_post);
    EXPECT_NEAR(cpu.stats.exposure, gl.stats.exposure, 2e-3 * gl.stats.exposure);
    ASSERT_EQ(cpu.ldr.pixels.size(), gl.ldr.pixels.size());
    int worst = 0, differ = 0, tinted = 0;
    for (std::size_t i = 0; i < gl.ldr.pixels.size(); i += 4) {
      for (std::size_t c = 0; c < 3; ++c) {
        const int d = std::abs(cpu.ldr.pixels[i + c] - gl.ldr.pixels[i + c]);
        worst = std::max(worst, d);
        differ += d > 0;
      }
      tinted += std::abs(gl.ldr.pixels[i] - gl.ldr.pixels[i + 2]) > 8;
      ASSERT_EQ(cpu.ldr.pixels[i + 3], 255);
    }
    const int pixels = 256 * 256;
    std::printf("colour at 1/%d: %d of %d values differ, by %d at most; %d pixels tinted\n", divisor, differ,
                3 * pixels, worst, tinted);
    EXPECT_GT(tinted, 20);  // a coloured picture, not a grey one in three channels
    EXPECT_LE(worst, 2);
    EXPECT_LT(differ, 3 * pixels / 50);
    ASSERT_EQ(cpu.i420.size(), gl.i420.size());
    int worst_yuv = 0;
    for (std::size_t i = 0; i < cpu.i420.size(); ++i) worst_yuv = std::max(worst_yuv, std::abs(cpu.i420[i] - gl.i420[i]));
    EXPECT_LE(worst_yuv, 2);
  }
}

TEST_F(CpuPostAgainstGl, ALocalToneMapStaysOnTheGl) {
  Scene s = straight_down_scene(4.0, 60.0, 30.0, 128);
  s.post.tone_map = ToneMap::local;
  EXPECT_FALSE(draw(s, TriangleSetup::cpu, 1).stats.cpu_post);
  s.render.wavelengths = 3;
  s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
  EXPECT_FALSE(draw(s, TriangleSetup::cpu, 1).stats.cpu_post);
}
