// SPDX-License-Identifier: LGPL-2.1-or-later
// The engine on scenes with closed-form answers (docs/physics.md ch. 7): the
// flat slab, a point light through index-1 glass and through a plate, and
// the render bookkeeping.
#include "gl_test_support.hpp"

#include "caustic/optics.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace caustic;
using namespace caustic::testing;

namespace {

// Pixels whose centre lies at least `margin` inside the square |x|,|y| <= half.
template <typename F>
void for_each_inside(const HdrImage& img, const ScreenParams& screen, double half, double margin, F&& f) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p = pixel_centre(screen, img.width, img.height, x, y);
      if (std::abs(p.x) <= half - margin && std::abs(p.y) <= half - margin) f(img.at(x, y), p);
    }
}

void expect_uniform(const HdrImage& img, const ScreenParams& screen, double half, double expected) {
  const double margin = 3.0 * screen.width / img.width;
  int count = 0;
  double worst = 0;
  for_each_inside(img, screen, half, margin, [&](float v, glm::dvec2) {
    worst = std::max(worst, std::abs(v - expected) / expected);
    ++count;
  });
  const double side = 2 * (half - margin);
  EXPECT_GT(count, 0.9 * side * side / (screen.width * screen.height) * img.width * img.height);
  EXPECT_LT(worst, 0.01) << "expected " << expected;
}

}  // namespace

class FlatSlab : public GlTest {
 protected:
  std::shared_ptr<const Mesh> slab = shared(grid_mesh(flat_face(10.0), 64, 64));
};

TEST_F(FlatSlab, WithoutFresnelTheFootprintReadsOne) {
  // 0.1 mm pixels: the slab's edges fall on pixel boundaries.
  const Scene s = straight_down_scene(3.0, 50.0, 25.6, 256);
  const HdrImage img = render(s, slab);
  expect_uniform(img, s.screen, 10.0, 1.0);
  // Outside the slab's shadow the object sends no light.
  EXPECT_EQ(img.at(2, 2), 0.0f);
  EXPECT_NEAR(total_flux(img, s.screen), 400.0, 400.0 * 1e-3);
}

TEST_F(FlatSlab, FresnelAtNormalIncidenceTransmits0_9216) {
  Scene s = straight_down_scene(3.0, 50.0, 24.0, 256);
  s.render.fresnel = true;
  expect_uniform(render(s, slab), s.screen, 10.0, 0.96 * 0.96);
}

TEST_F(FlatSlab, TiltedScreenReadsCosineOfTheTilt) {
  Scene s = straight_down_scene(3.0, 50.0, 40.0, 256);
  const double tilt = std::numbers::pi / 6;
  s.screen.normal = {0, std::sin(tilt), std::cos(tilt)};
  s.screen.up = {0, std::cos(tilt), -std::sin(tilt)};
  const HdrImage img = render(s, slab);
  // The footprint stretches to 20 / cos(tilt) along `up`; test its centre.
  expect_uniform(img, s.screen, 9.0, std::cos(tilt));
}

TEST_F(FlatSlab, ObliqueLightKeepsItsDirectionAndLosesFresnelTwice) {
  Scene s = straight_down_scene(3.0, 50.0, 40.0, 256);
  s.render.fresnel = true;
  const double theta = 0.35;  // 20 degrees
  s.light.direction = {std::sin(theta), 0, -std::cos(theta)};
  const double n = s.object.ior;
  const double cos_t = std::sqrt(1 - std::pow(std::sin(theta) / n, 2));
  // Unpolarised Fresnel (Hecht, eq. 4.42-4.43), written out: 1 - (r_s^2 + r_p^2) / 2.
  const auto fresnel_t = [](double cos_i, double cos_t, double n1, double n2) {
    const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    return 1 - 0.5 * (rs * rs + rp * rp);
  };
  const double t_in = fresnel_t(std::cos(theta), cos_t, 1.0, n);
  const double t_out = fresnel_t(cos_t, std::cos(theta), n, 1.0);
  // A parallel beam through parallel faces leaves parallel to the incident
  // light; the screen (normal +z) sees it at cos(theta), shifted sideways.
  const HdrImage img = render(s, slab);
  const double shift = 50.0 * std::tan(theta);
  int count = 0;
  for_each_inside(img, s.screen, 100.0, 0.0, [&](float v, glm::dvec2 p) {
    if (std::abs(p.x - shift) < 8 && std::abs(p.y) < 8) {
      EXPECT_NEAR(v, t_in * t_out * std::cos(theta), 0.01 * t_in * t_out) << p.x << "," << p.y;
      ++count;
    }
  });
  EXPECT_GT(count, 1000);
}

TEST_F(FlatSlab, ReportIntensityOfAParallelBeamIsOne) {
  Scene s = straight_down_scene(3.0, 50.0, 24.0, 128);
  s.render.intensity = IntensityMode::report;
  expect_uniform(render(s, slab), s.screen, 10.0, 1.0);
}

class PointLight : public GlTest {};

TEST_F(PointLight, IndexOneGlassShowsTheInverseSquareLaw) {
  // With n = 1 the object bends nothing: E / E0 = r_ref^2 cos(angle) / r^2.
  for (const auto model : {PointModel::exact, PointModel::approximate}) {
    Scene s = straight_down_scene(2.0, 40.0, 60.0, 256);
    s.object.ior = 1.0;
    s.light.type = LightType::point;
    s.light.point_model = model;
    s.light.position = {0, 0, 30};
    const auto mesh = shared(grid_mesh(flat_face(25.0), 128, 128));
    const HdrImage img = render(s, mesh);
    const double r_ref2 = 30.0 * 30.0;  // to the footprint centre
    double worst = 0;
    for (int y = 0; y < img.height; y += 3)
      for (int x = 0; x < img.width; x += 3) {
        const glm::dvec2 p = pixel_centre(s.screen, img.width, img.height, x, y);
        // Rays through the 50 mm object reach |x| < 25 * 70 / 30; stay inside.
        if (std::abs(p.x) > 25 || std::abs(p.y) > 25) continue;
        const glm::dvec3 to(p.x, p.y, -70.0);
        const double r2 = glm::dot(to, to);
        const double expected = r_ref2 * (70.0 / std::sqrt(r2)) / r2;
        worst = std::max(worst, std::abs(img.at(x, y) - expected) / expected);
      }
    EXPECT_LT(worst, 0.01) << (model == PointModel::exact ? "exact" : "approximate");
  }
}

TEST_F(PointLight, ThroughAPlateTheExactEntryFollowsTheRefractedInverseSquareLaw) {
  // A 2 mm plate of n = 1.5, the light 28 mm above its top, the screen 40 mm
  // below its bottom. The ray at angle t from the axis runs at t' (sin t =
  // n sin t') inside and leaves parallel to itself: it lands at
  // rs(t) = (H + D) tan t + h tan t', and the cone between t and t + dt
  // spreads over the ring between rs and rs + drs, so
  // E / E0 = r_ref^2 sin t / (rs drs/dt). Each pixel's t by bisection.
  const double n = 1.5, light_height = 28.0, thickness = 2.0, below = 40.0;
  Scene s = straight_down_scene(thickness, below, 60.0, 256);
  s.object.ior = n;
  s.light.type = LightType::point;
  s.light.point_model = PointModel::exact;
  s.light.position = {0, 0, thickness + light_height};
  // Each triangle spreads its flux evenly: 0.2 mm cells keep that to 0.3 %.
  const auto plate = shared(grid_mesh(flat_face(25.0), 256, 256));
  const auto landing = [&](double t) {
    return (light_height + below) * std::tan(t) + thickness * std::tan(std::asin(std::sin(t) / n));
  };
  const double r_ref2 = s.light.position.z * s.light.position.z;  // to the caustic face's centre
  const auto expected = [&](double rs) {
    double lo = 0, hi = 1.2;
    for (int i = 0; i < 60; ++i) (landing(0.5 * (lo + hi)) < rs ? lo : hi) = 0.5 * (lo + hi);
    const double t = 0.5 * (lo + hi), dt = 1e-6;
    return r_ref2 * std::sin(t) / (rs * (landing(t + dt) - landing(t - dt)) / (2 * dt));
  };
  // The GL's entry point (32 float halvings) and the CPU's (double).
  for (const TriangleSetup setup : {TriangleSetup::gpu, TriangleSetup::cpu}) {
    const char* path = setup == TriangleSetup::gpu ? "GL" : "CPU";
    engine_->set_triangle_setup(setup);
    const HdrImage img = render(s, plate);
    double worst = 0;
    for (int y = 0; y < img.height; y += 3)
      for (int x = 0; x < img.width; x += 3) {
        const double rs = glm::length(pixel_centre(s.screen, img.width, img.height, x, y));
        if (rs < 1.0) continue;  // the axis, where sin t / rs is 0 / 0
        worst = std::max(worst, std::abs(img.at(x, y) - expected(rs)) / expected(rs));
      }
    std::printf("point light through a plate, %s: worst %.5f of the refracted inverse-square law\n", path, worst);
    EXPECT_LT(worst, 0.01) << path;
  }
}

class RenderBookkeeping : public GlTest {};

TEST_F(RenderBookkeeping, RendersOnlyWhenSomethingChanged) {
  const auto mesh = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = straight_down_scene(3.0, 50.0, 24.0, 64);
  engine_->set_scene(s, mesh);
  EXPECT_TRUE(engine_->render());
  EXPECT_FALSE(engine_->render());
  engine_->set_scene(s, mesh);
  EXPECT_FALSE(engine_->dirty());
  EXPECT_EQ(engine_->ray_passes(), 1u);

  s.post.exposure = 2.0;  // post-processing only: no new caustic pass
  engine_->set_scene(s, mesh);
  EXPECT_TRUE(engine_->render());
  EXPECT_EQ(engine_->ray_passes(), 1u);

  s.light.direction = glm::normalize(glm::dvec3(0.1, 0, -1));
  engine_->set_scene(s, mesh);
  EXPECT_TRUE(engine_->render());
  EXPECT_EQ(engine_->ray_passes(), 2u);
}

TEST_F(RenderBookkeeping, InvalidScenesNeverReachTheGpu) {
  const auto mesh = shared(grid_mesh(flat_face(10.0), 16, 16));
  const Scene good = straight_down_scene(3.0, 50.0, 24.0, 64);
  const HdrImage before = render(good, mesh);
  for (int k = 0; k < 4; ++k) {
    Scene bad = good;
    if (k == 0) bad.object.ior = std::nan("");
    if (k == 1) bad.light.direction = {0, INFINITY, -1};
    if (k == 2) bad.screen.width = -1;
    if (k == 3) bad.screen.center = {0, 0, 1};  // crosses the object
    EXPECT_THROW(engine_->set_scene(bad, mesh), SceneError) << k;
    EXPECT_FALSE(engine_->dirty());
  }
  EXPECT_EQ(engine_->read_hdr().pixels, before.pixels);
}

TEST_F(RenderBookkeeping, ToneMappedImageFollowsExposureAndGamma) {
  const auto mesh = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = straight_down_scene(3.0, 50.0, 24.0, 64);
  s.post.bloom_strength = 0;
  s.post.exposure = 0.7;
  s.post.gamma = 2.0;
  engine_->set_scene(s, mesh);
  engine_->render();
  const Rgba8Image ldr = engine_->read_ldr();
  // Centre pixel: relative irradiance 1.0 -> (1 - exp(-0.7))^(1/2).
  const std::size_t centre = (static_cast<std::size_t>(32) * 64 + 32) * 4;
  EXPECT_NEAR(ldr.pixels[centre], 255.0 * std::sqrt(1 - std::exp(-0.7)), 1.0);
  EXPECT_EQ(ldr.pixels[0], 0);
  EXPECT_EQ(ldr.pixels[3], 255);
}

TEST_F(RenderBookkeeping, BloomSpreadsLightAboveTheThreshold) {
  // A small bright square (the slab at 4x4 mm) on a dark screen.
  const auto mesh = shared(grid_mesh(flat_face(2.0), 8, 8));
  Scene s = straight_down_scene(3.0, 50.0, 25.6, 128);
  s.post.exposure = 1.0;
  s.post.bloom_threshold = 0.5;
  s.post.bloom_radius = 6.0;
  auto pixel_beside = [&](double strength) {
    s.post.bloom_strength = strength;
    engine_->set_scene(s, mesh);
    engine_->render();
    const Rgba8Image ldr = engine_->read_ldr();
    // 1 mm (5 pixels) right of the square's edge, on its middle row.
    return ldr.pixels[(static_cast<std::size_t>(64) * 128 + 64 + 10 + 5) * 4];
  };
  EXPECT_EQ(pixel_beside(0.0), 0);
  EXPECT_GT(pixel_beside(1.0), 10);
  s.post.bloom_threshold = 2.0;  // above the slab's 1.0: nothing blooms
  EXPECT_EQ(pixel_beside(1.0), 0);
}

TEST_F(RenderBookkeeping, AsynchronousReadBackDeliversTheNewestPicture) {
  const auto mesh = shared(grid_mesh(flat_face(10.0), 16, 16));
  Scene s = straight_down_scene(3.0, 50.0, 24.0, 64);
  Rgba8Image picture;
  std::uint64_t tag = 0;
  EXPECT_FALSE(engine_->poll_ldr_readback(&picture, &tag, false));  // nothing queued
  engine_->set_scene(s, mesh);
  engine_->render();
  const Rgba8Image first = engine_->read_ldr();
  engine_->start_readback(7);
  s.post.exposure = 3.0;
  engine_->set_scene(s, mesh);
  engine_->render();
  const Rgba8Image second = engine_->read_ldr();
  ASSERT_NE(first.pixels, second.pixels);
  engine_->start_readback(8);
  ASSERT_TRUE(engine_->poll_ldr_readback(&picture, &tag, true));
  EXPECT_EQ(tag, 8u);  // the newer picture; the older one is dropped
  EXPECT_EQ(picture.width, 64);
  EXPECT_EQ(picture.pixels, second.pixels);
  EXPECT_FALSE(engine_->poll_ldr_readback(&picture, &tag, false));
}

namespace {

// The largest difference between `i420` and the BT.601 limited-range
// conversion of `rgba` (Y = 16 + 219 Y', chroma 128 + 224 (B'-Y')/1.772 and
// (R'-Y')/1.402 over each 2x2 block), plane by plane; `lit` counts the Y
// samples above 40.
int worst_i420_error(const Rgba8Image& rgba, const std::vector<std::uint8_t>& i420, int* lit) {
  const int w = rgba.width, h = rgba.height;
  auto channel = [&](int x, int y, int c) { return rgba.pixels[(static_cast<std::size_t>(y) * w + x) * 4 + c] / 255.0; };
  auto luma = [&](int x, int y) { return 0.299 * channel(x, y, 0) + 0.587 * channel(x, y, 1) + 0.114 * channel(x, y, 2); };
  int worst = 0;
  *lit = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int expected = static_cast<int>(std::lround(16 + 219 * luma(x, y)));
      worst = std::max(worst, std::abs(expected - i420[static_cast<std::size_t>(y) * w + x]));
      *lit += expected > 40;
    }
  const std::size_t u0 = static_cast<std::size_t>(w) * h, v0 = u0 + static_cast<std::size_t>(w / 2) * (h / 2);
  for (int y = 0; y < h / 2; ++y)
    for (int x = 0; x < w / 2; ++x) {
      double yy = 0, b = 0, r = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          yy += luma(2 * x + dx, 2 * y + dy) / 4;
          b += channel(2 * x + dx, 2 * y + dy, 2) / 4;
          r += channel(2 * x + dx, 2 * y + dy, 0) / 4;
        }
      const std::size_t i = static_cast<std::size_t>(y) * (w / 2) + x;
      worst = std::max(worst, std::abs(static_cast<int>(std::lround(128 + 224 * (b - yy) / 1.772)) - i420[u0 + i]));
      worst = std::max(worst, std::abs(static_cast<int>(std::lround(128 + 224 * (r - yy) / 1.402)) - i420[v0 + i]));
    }
  return worst;
}

}  // namespace

// The GPU's I420 against the tone-mapped RGBA converted here on the CPU, for
// a grey frame (whose chroma the engine clears rather than computes) and a
// colour one (a tinted lens).
TEST_F(FlatSlab, I420ReadBackIsTheToneMappedPictureConvertedOnTheGpu) {
  Mesh lens = grid_mesh(plano_convex_lens(40.0, 10.0), 64, 64);
  const auto mesh = shared(lens);
  Scene s = straight_down_scene(4.0, 60.0, 30.0, 64);
  s.render.width = 72;  // not square, width a multiple of 8 but not of 16, height even but not a multiple of 4
  s.render.height = 50;
  s.render.fresnel = true;
  s.post.exposure = 0.7;
  const int w = 72, h = 50;
  lens.colours.resize(lens.positions.size());
  for (std::size_t i = 0; i < lens.colours.size(); ++i)
    lens.colours[i] = lens.positions[i].x > 0 ? glm::vec3(1.0f, 0.3f, 0.1f) : glm::vec3(0.2f, 0.5f, 1.0f);
  for (const auto& m : {mesh, shared(lens)}) {
    engine_->set_scene(s, m);
    engine_->render();
    SCOPED_TRACE(engine_->stats().colour ? "colour" : "grey");
    const Rgba8Image rgba = engine_->read_ldr();
    ASSERT_EQ(engine_->picture_bytes(PixelFormat::i420), static_cast<std::size_t>(w * h * 3 / 2));
    std::vector<std::uint8_t> i420(engine_->picture_bytes(PixelFormat::i420));
    std::uint64_t tag = 0;
    engine_->start_readback(3, PixelFormat::i420);
    ASSERT_TRUE(engine_->poll_readback(i420.data(), i420.size(), &tag, true));
    EXPECT_EQ(tag, 3u);
    int lit = 0;
    EXPECT_LE(worst_i420_error(rgba, i420, &lit), 1);
    EXPECT_GT(lit, 100);  // the lens's disc, not a black frame
  }
  EXPECT_TRUE(engine_->stats().colour);
  // A size the packed layout cannot hold is refused.
  s.render.width = 68;
  engine_->set_scene(s, mesh);
  engine_->render();
  EXPECT_THROW(engine_->start_readback(4, PixelFormat::i420), EngineError);
}
