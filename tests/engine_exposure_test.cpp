// SPDX-License-Identifier: LGPL-2.1-or-later
// Automatic exposure and the local tone map (docs/physics.md, "Exposure").
// Oracles: an evenly lit screen (a flat slab) lands at the metered level,
// 255 (1 - exp(-knee))^(1/gamma) = 235 of 255, whatever its irradiance; the
// GPU meter bins like its CPU twin; and every built-in scene at its defaults
// clips at most 1% of its lit pixels and keeps its brightest structure
// brighter than its surroundings in the 8-bit picture.
#include "caustic/exposure.hpp"
#include "gl_test_support.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <numbers>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

using namespace caustic;
using namespace caustic::testing;

namespace {

class Exposure : public GlTest {};

Scene auto_scene(double distance) {
  Scene s = straight_down_scene(3.0, distance, 51.2, 256);
  s.post.exposure_mode = ExposureMode::automatic;
  s.post.bloom_strength = 0;
  return s;
}

// The grey level of pixel i.
int grey(const Rgba8Image& ldr, std::size_t i) { return ldr.pixels[4 * i]; }

// Renders until the shown exposure has settled (bounded in count: the
// settling is in wall-clock time, so a loaded machine only takes more rounds).
// Each frame at least a millisecond apart: the easing follows the clock,
// and a post-only frame of a small picture can take less than that (2000
// of them back to back once ended short of the ~0.2 s the easing needs).
void settle(Engine& engine) {
  for (int i = 0; i < 2000 && engine.dirty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    engine.render();
  }
}

}  // namespace

TEST_F(Exposure, AnEvenlyLitScreenLandsAtTheMeteredLevel) {
  // A flat slab: relative irradiance 1 wherever the light lands.
  const double knee_level = 255.0 * exposure::kMeteredLevel;
  const auto mesh = shared(grid_mesh(flat_face(2.0), 8, 8));
  Scene s = auto_scene(50.0);
  s.post.exposure_adapt_s = 0;
  const HdrImage hdr = render(s, mesh);
  const Rgba8Image ldr = engine_->read_ldr();
  int lit = 0;
  for (std::size_t i = 0; i < hdr.pixels.size(); ++i) {
    if (!(hdr.pixels[i] > 0.5f)) continue;
    ++lit;
    // Within the histogram's bin width (1/8 stop) of the knee.
    ASSERT_NEAR(grey(ldr, i), knee_level, 6.0) << "pixel " << i << " at irradiance " << hdr.pixels[i];
  }
  EXPECT_GT(lit, 100);
  // The GPU meter agrees with its CPU twin on the same image.
  const double metered = engine_->stats().exposure;
  EXPECT_NEAR(metered, exposure::settled_exposure(s.post, hdr), 1e-3 * metered);
  // Compensation multiplies the metered exposure exactly.
  s.post.exposure = 0.25;
  engine_->set_scene(s, mesh);
  engine_->render();
  EXPECT_NEAR(engine_->stats().exposure, 0.25 * metered, 1e-6 * metered);
}

TEST_F(Exposure, ManualExposureIsUsedAsWritten) {
  const auto mesh = shared(grid_mesh(flat_face(2.0), 8, 8));
  Scene s = auto_scene(50.0);
  s.post.exposure_mode = ExposureMode::manual;
  s.post.exposure = 0.37;
  render(s, mesh);
  EXPECT_EQ(engine_->stats().exposure, static_cast<double>(0.37));
  EXPECT_FALSE(engine_->dirty());
}

TEST_F(Exposure, AChangeEasesInAndThenSettles) {
  // A lens focuses the same flux onto less area: the meter asks for less
  // exposure. With a time constant the first frame after the change shows
  // an exposure between the old and the new one, and the picture then keeps
  // redrawing (post-processing only) until it lands on the new one.
  const auto flat = shared(grid_mesh(flat_face(2.0), 32, 32));
  const auto lens = shared(grid_mesh(plano_convex_lens(40.0, 2.0), 64, 64));
  Scene s = auto_scene(50.0);
  s.post.exposure_adapt_s = 5.0;  // long enough that no frame on any machine lands at once
  render(s, flat);
  const double before = engine_->stats().exposure;
  const auto passes = engine_->ray_passes();
  engine_->set_scene(s, lens);  // a new mesh starts afresh: no easing from another object
  engine_->render();
  const double lens_exposure = engine_->stats().exposure;
  EXPECT_LT(lens_exposure, 0.8 * before);
  engine_->set_scene(s, flat);
  engine_->render();  // a new mesh again: lands at once
  EXPECT_NEAR(engine_->stats().exposure, before, 1e-9 * before);

  // Same mesh, dimmer light: on the screen turned 60 degrees the beam
  // spreads over twice the area (Lambert), so the metered irradiance halves
  // and the exposure doubles, easing in.
  const double theta = std::numbers::pi / 3;
  s.screen.normal = {std::sin(theta), 0, std::cos(theta)};
  engine_->set_scene(s, flat);
  engine_->render();
  const double first = engine_->stats().exposure;
  // A frame moves the exposure by 1 - exp(-dt / 5 s) of the way (in stops),
  // dt counted at most 0.5 s: under a tenth, however slow the machine. A
  // change that landed at once would be all the way (twice `before`).
  EXPECT_GE(first, before);
  EXPECT_LT(first, before * std::sqrt(2.0)) << "the change did not ease in";
  s.post.exposure_adapt_s = 0.05;  // then settles in a few frames
  engine_->set_scene(s, flat);
  settle(*engine_);
  EXPECT_FALSE(engine_->dirty()) << "the exposure never settled";
  const double settled = engine_->stats().exposure;
  EXPECT_GE(settled, first);
  // The meter's bins are 1/8 stop (9%) wide.
  EXPECT_NEAR(settled / before, 1 / std::cos(theta), 0.09 / std::cos(theta));
  EXPECT_GT(engine_->ray_passes(), passes);
  EXPECT_EQ(engine_->ray_passes(), passes + 3) << "easing redrew the caustic instead of only the tone map";
}

// Every built-in scene at its defaults (the shipped post settings, full
// size, the mesh as shipped).
class BuiltInExposure : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(BuiltInExposure, ClipsAtMostOnePercentAndKeepsTheBrightestStructureVisible) {
  const std::string file = std::string(CAUSTIC_ASSET_DIR) + "/scenes/" + GetParam() + ".json";
  if (GetParam().rfind("design-", 0) == 0 && !std::filesystem::exists(file))
    GTEST_SKIP() << GetParam() << " was not built (CAUSTICD_DESIGN_PHOTO_DIR)";
  for (const ToneMap tone_map : {ToneMap::global, ToneMap::local}) {
    Scene scene = load_scene(file);
    scene.post.tone_map = tone_map;
    engine_ = std::make_unique<Engine>();
    const HdrImage hdr = render(scene, shared(load_obj(scene.mesh_path())));
    settle(*engine_);
    const Rgba8Image ldr = engine_->read_ldr();
    std::size_t lit = 0, clipped = 0, peak = 0;
    for (std::size_t i = 0; i < hdr.pixels.size(); ++i) {
      if (hdr.pixels[i] > hdr.pixels[peak]) peak = i;
      if (!(hdr.pixels[i] > std::exp2(exposure::kLog2Lit))) continue;
      ++lit;
      if (grey(ldr, i) == 255) ++clipped;
    }
    ASSERT_GT(lit, 0u);
    const double clipped_share = static_cast<double>(clipped) / static_cast<double>(lit);
    // The brightest structure: the grey at the HDR peak against the mean grey
    // of the ring 6 to 12 pixels around it.
    const int px = static_cast<int>(peak % hdr.width), py = static_cast<int>(peak / hdr.width);
    double ring = 0;
    int ring_n = 0;
    for (int dy = -12; dy <= 12; ++dy)
      for (int dx = -12; dx <= 12; ++dx) {
        const int r2 = dx * dx + dy * dy, x = px + dx, y = py + dy;
        if (r2 < 36 || r2 > 144 || x < 0 || y < 0 || x >= hdr.width || y >= hdr.height) continue;
        ring += grey(ldr, static_cast<std::size_t>(y) * hdr.width + x);
        ++ring_n;
      }
    ring /= std::max(ring_n, 1);
    const int at_peak = grey(ldr, peak);
    std::printf("%s (%s): %.2f%% of %zu lit pixels at 255; peak grey %d, ring around it %.1f; exposure %.4g\n",
                GetParam().c_str(), tone_map == ToneMap::local ? "local" : "global", 100 * clipped_share, lit,
                at_peak, ring, engine_->stats().exposure);
    EXPECT_LE(clipped_share, 0.01);
    // An evenly lit scene has no structure to keep; elsewhere the peak is
    // at least 8 grey levels above its surroundings.
    if (hdr.pixels[peak] > 2 * exposure::quantile(exposure::histogram(hdr), 0.5)) {
      EXPECT_GE(at_peak - ring, 8.0) << "the brightest structure merges into its surroundings";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BuiltInExposure, ::testing::ValuesIn(kShippedScenes), scene_test_name);
