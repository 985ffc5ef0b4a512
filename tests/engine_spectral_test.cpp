// SPDX-License-Identifier: LGPL-2.1-or-later
// Spectral frames against closed forms (docs/physics.md §10): white light
// through a flat slab stays white; a wedge of BK7 sends each colour channel
// where Snell's law sends its wavelengths, and near the critical angle the
// blue is lost to total internal reflection before the red.
#include "gl_test_support.hpp"

#include "caustic/spectral.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace caustic;
using namespace caustic::testing;

namespace {

// Deviation from straight down of light leaving the wedge's face, by Snell's
// law: sin(theta_t) = n sin(alpha), deviated by theta_t - alpha towards -x
// (the prism's base, where the glass is thicker).
double wedge_deviation(double n, double alpha) { return std::asin(n * std::sin(alpha)) - alpha; }

struct Channels {
  double sum[3] = {0, 0, 0};
  double moment_x[3] = {0, 0, 0};  // sum of value * screen x
  double centroid(int c) const { return moment_x[c] / sum[c]; }
};

Channels channels(const RgbHdrImage& img, const ScreenParams& screen) {
  Channels ch;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double px = pixel_centre(screen, img.width, img.height, x, y).x;
      for (int c = 0; c < 3; ++c) {
        const double v = img.pixels[3 * (static_cast<std::size_t>(y) * img.width + x) + c];
        ch.sum[c] += v;
        ch.moment_x[c] += v * px;
      }
    }
  return ch;
}

class Spectral : public GlTest {
 protected:
  static Scene bk7(Scene s, int wavelengths) {
    s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
    s.object.ior = s.object.glass->index(optics::kLineD);
    s.render.wavelengths = wavelengths;
    return s;
  }
};

}  // namespace

TEST_F(Spectral, WhiteLightThroughAFlatSlabStaysWhite) {
  const auto slab = shared(grid_mesh(flat_face(10.0), 32, 32));
  for (const auto spectrum : {optics::LightSpectrum{optics::Illuminant::d65},
                              optics::LightSpectrum{optics::Illuminant::blackbody, 2700},
                              optics::LightSpectrum{optics::Illuminant::led}}) {
    Scene s = bk7(straight_down_scene(3.0, 50.0, 25.6, 128), 8);
    s.light.spectrum = spectrum;
    const RgbHdrImage img = render_rgb(s, slab);
    EXPECT_EQ(engine_->stats().wavelengths, 8);
    int lit = 0;
    double worst = 0;
    for (std::size_t i = 0; i < img.pixels.size(); i += 3) {
      const double r = img.pixels[i], g = img.pixels[i + 1], b = img.pixels[i + 2];
      if (r + g + b < 1.5) continue;  // the footprint reads 1 per channel
      ++lit;
      worst = std::max({worst, std::abs(r / (r + g + b) - 1.0 / 3), std::abs(g / (r + g + b) - 1.0 / 3)});
    }
    EXPECT_GT(lit, 5000);
    EXPECT_LT(worst, 1e-3);
    // White-balanced weights sum to one: the luminance is the monochrome frame's.
    EXPECT_NEAR(total_flux(luminance(img), s.screen), 400.0, 400.0 * 1e-3);
  }
}

TEST_F(Spectral, AWedgeSendsEachChannelWhereSnellSendsItsWavelengths) {
  const double alpha = 0.35, distance = 100.0;  // a 20 degree prism, screen 100 mm below
  const auto prism = shared(grid_mesh(wedge(alpha, 5.0, 5.0), 16, 16));
  Scene s = bk7(straight_down_scene(5.0, distance, 40.0, 512), 8);
  s.screen.center.x = -distance * wedge_deviation(1.52, alpha);  // centred on the spectrum
  const RgbHdrImage img = render_rgb(s, prism);
  const Channels ch = channels(img, s.screen);

  // With Fresnel off every wavelength carries the same flux; a channel's
  // centroid is its bands' spots averaged with the band weights.
  const auto passes = spectral_passes(s, 8);
  ASSERT_EQ(passes.size(), 8u);
  double expected[3] = {0, 0, 0};
  for (const auto& p : passes) {
    // The index from the catalogue law at the band's wavelength, not the pass's own.
    const double n = optics::index(optics::find_material("bk7")->law, p.nm);
    const double x = -distance * std::tan(wedge_deviation(n, alpha));
    expected[0] += p.weight.r * x;
    expected[1] += p.weight.g * x;
    expected[2] += p.weight.b * x;
  }
  for (int c = 0; c < 3; ++c) {
    const double measured = std::atan(-(s.screen.center.x + ch.centroid(c)) / distance), analytic = std::atan(-expected[c] / distance);
    EXPECT_NEAR(measured, analytic, 1e-4) << "channel " << c;
  }
  // Blue bends most: the spread between the red and blue centroids against
  // the analytic one.
  const double spread = ch.centroid(0) - ch.centroid(2), analytic_spread = expected[0] - expected[2];
  EXPECT_GT(spread, 0.0);
  EXPECT_NEAR(spread, analytic_spread, 0.01 * analytic_spread);
  // Every band passes the 10 x 10 mm face's 100 mm^2 of light, and a
  // channel's weights sum to one: no channel loses any of it.
  const double pixel_area = (40.0 / 512) * (40.0 / 512);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(ch.sum[c] * pixel_area, 100.0, 0.1) << "channel " << c;
}

TEST_F(Spectral, NearTheCriticalAngleBlueIsLostBeforeRed) {
  // BK7's critical angle is 40.8 degrees at 405 nm and 41.4 at 755 nm
  // (its Sellmeier law): at 41 degrees the bands below about 460 nm reflect
  // totally, the longer ones pass whole (Fresnel off).
  const double alpha = 41.0 * M_PI / 180;
  const auto prism = shared(grid_mesh(wedge(alpha, 5.0, 5.0), 16, 16));
  Scene s = bk7(straight_down_scene(5.0, 20.0, 200.0, 256), 8);
  s.screen.center.x = -60;
  const RgbHdrImage img = render_rgb(s, prism);
  for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v));
  const Channels ch = channels(img, s.screen);
  EXPECT_GT(ch.sum[0], 5 * std::abs(ch.sum[2])) << "what passes is red";
  // Each channel: the face's 100 mm^2 of light times the weights of the
  // bands whose index, by the catalogue law, lets them out (n sin alpha < 1).
  double expected[3] = {0, 0, 0};
  int lost = 0;
  for (const auto& p : spectral_passes(s, 8)) {
    if (optics::index(optics::find_material("bk7")->law, p.nm) * std::sin(alpha) >= 1) {
      ++lost;
      continue;
    }
    expected[0] += 100 * p.weight.r, expected[1] += 100 * p.weight.g, expected[2] += 100 * p.weight.b;
  }
  EXPECT_EQ(lost, 2);  // 405 and 455 nm
  const double pixel_area = (200.0 / 256) * (200.0 / 256);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(ch.sum[c] * pixel_area, expected[c], 1e-3 * std::abs(expected[0])) << "channel " << c;
}

TEST_F(Spectral, AtGrazingIncidenceEveryWavelengthStaysFiniteAndConservesFlux) {
  // 85 degrees from the normal: each wavelength refracts to its own angle
  // inside (about 40.6 to 41.0 degrees in BK7) and leaves parallel to the
  // light; the slab's 20 x 20 mm face intercepts 400 cos(85 deg) mm² of it.
  const auto slab = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = bk7(straight_down_scene(3.0, 20.0, 400.0, 512), 8);
  const double theta = 85.0 * M_PI / 180;
  s.light.direction = {std::sin(theta), 0, -std::cos(theta)};
  s.screen.center.x = 20.0 * std::tan(theta);
  s.screen.width = 600;
  const RgbHdrImage img = render_rgb(s, slab);
  for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v));
  ScreenParams screen = s.screen;
  EXPECT_NEAR(total_flux(luminance(img), screen), 400.0 * std::cos(theta), 400.0 * std::cos(theta) * 1e-3);
  // Flat faces: no wavelength bends for good, so the frame stays white.
  const Channels ch = channels(img, s.screen);
  EXPECT_NEAR(ch.sum[0] / ch.sum[2], 1.0, 1e-3);
}

TEST_F(Spectral, APreviewTracesAtMostThreeWavelengths) {
  const auto slab = shared(grid_mesh(flat_face(10.0), 16, 16));
  engine_->set_preview_divisor(2);
  render_rgb(bk7(straight_down_scene(3.0, 50.0, 25.6, 128), 16), slab);
  EXPECT_EQ(engine_->stats().wavelengths, 3);  // the preview count, not the code's constant
  engine_->set_preview_divisor(1);
  engine_->render();
  EXPECT_EQ(engine_->stats().wavelengths, 16);
}

TEST_F(Spectral, WithoutAGlassTheFrameIsMonochrome) {
  const auto slab = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = straight_down_scene(3.0, 50.0, 25.6, 128);
  s.render.wavelengths = 16;  // moot without dispersion: one pass
  const RgbHdrImage img = render_rgb(s, slab);
  EXPECT_EQ(engine_->stats().wavelengths, 1);
  const std::size_t centre = 3 * (64 * 128 + 64);
  EXPECT_NEAR(img.pixels[centre], 1.0f, 1e-5);
  EXPECT_EQ(img.pixels[centre], img.pixels[centre + 1]);
  EXPECT_EQ(img.pixels[centre], img.pixels[centre + 2]);
}

namespace {

// Columns of `img` (luminance summed down each) strictly between its first
// and last lit ones that get no light at all: gaps between the spots of a
// spectrum sampled too coarsely for the beam's width.
int dark_columns_inside(const RgbHdrImage& img) {
  std::vector<double> column(static_cast<std::size_t>(img.width), 0.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = &img.pixels[3 * (static_cast<std::size_t>(y) * img.width + x)];
      column[static_cast<std::size_t>(x)] += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
  const double peak = *std::max_element(column.begin(), column.end());
  int first = -1, last = -1, dark = 0;
  for (int x = 0; x < img.width; ++x)
    if (column[static_cast<std::size_t>(x)] > 1e-9 * peak) (first < 0 ? first : last) = x, last = x;
  for (int x = first + 1; x < last; ++x) dark += column[static_cast<std::size_t>(x)] <= 1e-9 * peak;
  return dark;
}

}  // namespace

TEST_F(Spectral, APictureLeftStandingSamplesItsStillWavelengths) {
  // A narrow beam through a wedge: Snell's law fans the visible spectrum
  // over about a millimetre 100 mm down, a continuous band of colour. Eight
  // wavelengths land eight separate images of the 0.1 mm beam, further
  // apart in the blue than the beam is wide; thirty-two land closer than
  // that everywhere, and the band closes.
  const double alpha = 0.35, distance = 100.0, half_width = 0.05;
  const auto prism = shared(grid_mesh(wedge(alpha, half_width, 2.0), 16, 16));
  Scene s = bk7(straight_down_scene(5.0, distance, 1.6, 512), 8);
  s.screen.center.x = -distance * std::tan(wedge_deviation(1.52, alpha));
  s.render.still_wavelengths = 32;
  // The analytic spacing of each sampling's neighbouring images against the beam's width.
  const auto widest_gap = [&](int k) {
    const auto passes = spectral_passes(s, k);
    double widest = 0;
    for (std::size_t i = 1; i < passes.size(); ++i) {
      const auto x = [&](double nm) {
        return distance * std::tan(wedge_deviation(optics::index(optics::find_material("bk7")->law, nm), alpha));
      };
      widest = std::max(widest, std::abs(x(passes[i].nm) - x(passes[i - 1].nm)));
    }
    return widest;
  };
  const double beam = 2 * half_width * (1 - std::tan(alpha) * std::tan(wedge_deviation(1.52, alpha)));
  ASSERT_GT(widest_gap(8), 1.5 * beam);
  ASSERT_LT(widest_gap(32), 0.9 * beam);

  const RgbHdrImage moving = render_rgb(s, prism);
  EXPECT_EQ(engine_->stats().wavelengths, 8);
  EXPECT_GT(dark_columns_inside(moving), 20) << "eight wavelengths leave gaps in the spectrum";

  engine_->set_still(true);
  ASSERT_TRUE(engine_->dirty());
  engine_->render();
  EXPECT_EQ(engine_->stats().wavelengths, 32);
  const RgbHdrImage still = engine_->read_hdr_rgb();
  EXPECT_EQ(dark_columns_inside(still), 0) << "the spectrum left standing is one band";
  // The same light, only finer in wavelength: the luminance's total is kept.
  EXPECT_NEAR(total_flux(luminance(still), s.screen), total_flux(luminance(moving), s.screen),
              1e-3 * total_flux(luminance(moving), s.screen));

  // A preview while standing is still a preview; letting go draws the full frame's count again.
  engine_->set_preview_divisor(2);
  engine_->render();
  EXPECT_EQ(engine_->stats().wavelengths, 3);
  engine_->set_preview_divisor(1);
  engine_->set_still(false);
  engine_->render();
  EXPECT_EQ(engine_->stats().wavelengths, 8);
}

TEST_F(Spectral, StandingStillAddsNothingWhereThereIsNothingToAdd) {
  const auto slab = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = bk7(straight_down_scene(3.0, 50.0, 25.6, 128), 16);
  s.render.still_wavelengths = 8;  // fewer than a full frame's: the full frame's count stands
  render_rgb(s, slab);
  engine_->set_still(true);
  EXPECT_FALSE(engine_->dirty());
  Scene grey = straight_down_scene(3.0, 50.0, 25.6, 128);  // no glass: one grey pass, standing or not
  render_rgb(grey, slab);
  engine_->set_still(false);
  EXPECT_FALSE(engine_->dirty());
  engine_->set_still(true);
  EXPECT_FALSE(engine_->dirty());
}
