// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic designer against oracles that do not trust it: closed-form
// transport maps, the plano-hyperbolic lens, energy conservation, symmetry,
// the paraxial scaling with the focus, and the solid's topology. Renders go
// through the engine, never through the designer's own estimates.
#include "face.hpp"
#include "gl_test_support.hpp"
#include "heights.hpp"

#include "caustic/design.hpp"
#include "caustic/design_verify.hpp"
#include "caustic/image_io.hpp"
#include "refusal.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

using namespace caustic;
using namespace caustic::design;
using namespace caustic::testing;

namespace {

/// An n x n picture from f(u, v) at cell centres, u along +x and v along +y
/// in [0, 1] (row 0 is the top, v near 1).
Image picture(int n, const std::function<double(double, double)>& f) {
  Image img{n, n, std::vector<float>(std::size_t(n) * n)};
  for (int row = 0; row < n; ++row)
    for (int i = 0; i < n; ++i)
      img.pixels[std::size_t(row) * n + i] = static_cast<float>(f((i + 0.5) / n, 1 - (row + 0.5) / n));
  return img;
}

DesignOptions options(int n) {
  DesignOptions o;
  o.resolution = n;
  o.tolerance = 1e-9;
  o.max_iterations = 2000;
  o.height_tolerance = 1e-7;
  o.max_snell_passes = 8;
  return o;
}

// A smooth, mirror-symmetric (x -> -x) picture of moderate contrast.
double smooth_blobs(double u, double v) {
  const auto g = [](double du, double dv, double s) { return std::exp(-(du * du + dv * dv) / (2 * s * s)); };
  return 0.4 + 0.6 * g(u - 0.3, v - 0.6, 0.12) + 0.6 * g(u - 0.7, v - 0.6, 0.12) + 0.5 * g(u - 0.5, v - 0.25, 0.1);
}

}  // namespace

class Designer : public GlTest {};

TEST_F(Designer, UniformTargetGivesAFlatFaceAndAUniformCaustic) {
  const Design d = design_face(picture(64, [](double, double) { return 0.7; }), options(64));
  EXPECT_LT(d.report.relief, 1e-9 * d.options.size);
  EXPECT_EQ(d.report.tir_vertices, 0);
  const Verification v = verify_with_engine(d);
  double worst = 0;
  for (float p : v.render.pixels) worst = std::max(worst, std::abs(p - 1.0));
  EXPECT_LT(worst, 1e-3) << "largest deviation from a uniform 1";
}

TEST_F(Designer, TwoLevelRampFollowsTheAnalyticMap) {
  // Left half 0.25, right half 1: the map is 1-D, X(x) = CDF(x), with
  // CDF = 0.4 x below x = 1/2 and 0.2 + 1.6 (x - 1/2) above. n = 80 puts
  // the lens image of the step (X = 0.2) on a vertex column.
  const int n = 80;
  const Design d = design_face(picture(n, [](double u, double) { return u < 0.5 ? 0.25 : 1.0; }), options(n));
  const auto cdf = [](double x) { return x < 0.5 ? 0.4 * x : 0.2 + 1.6 * (x - 0.5); };
  double worst = 0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const glm::dvec2 X = d.warped[std::size_t(j) * (n + 1) + i];
      worst = std::max({worst, std::abs(X.x - cdf(double(i) / n)), std::abs(X.y - double(j) / n)});
    }
  EXPECT_LT(worst, 1e-6) << "largest distance from the analytic map (lens widths)";
  const Verification v = verify_with_engine(d);
  std::printf("ramp: relative L1 %.4f%%, SSIM %.4f\n", 100 * v.relative_l1, v.ssim);
  EXPECT_LT(v.relative_l1, 0.005);
}

TEST_F(Designer, BrightSquareOnAFloorKeepsItsShareOfTheLight) {
  // a = 1/16 of the screen at density 1, the rest at the floor eps: the
  // square gets the share a / (a + eps (1 - a)) of the light, spread over a.
  const int n = 64;
  const double a = 1.0 / 16, eps = 1e-2;
  DesignOptions o = options(n);
  o.black_floor = eps;
  const Design d = design_face(
      picture(n, [](double u, double v) { return std::abs(u - 0.5) < 0.125 && std::abs(v - 0.5) < 0.125 ? 1.0 : 0.0; }), o);
  EXPECT_EQ(d.report.tir_vertices, 0);
  const Verification v = verify_with_engine(d);
  double inside = 0;
  int count = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (x >= 24 && x < 40 && y >= 24 && y < 40) inside += v.render.at(x, y), ++count;
  const double expected_inside = (1 / a) * a / (a + eps * (1 - a));
  const double expected_leak = eps * (1 - a) / (a + eps * (1 - a));
  std::printf("square: inside %.4f (expected %.4f), light on black %.4f (expected %.4f)\n", inside / count,
              expected_inside, v.leak, expected_leak);
  EXPECT_NEAR(inside / count / expected_inside, 1.0, 0.01);
  EXPECT_NEAR(v.leak / expected_leak, 1.0, 0.10);
}

namespace {
// Plano-hyperbolic lens focusing collimated light (inside glass, going -z)
// to the point at depth `focus` below the vertex: sqrt(r^2 + z^2) =
// n z - (n - 1) d with z measured up from the focus and d the vertex's z
// (a hyperbola of eccentricity n). Returns z(r) - d.
double hyperbola_sag(double r, double d, double n) {
  const double b = n * (n - 1) * d, c = (n - 1) * (n - 1) * d * d - r * r;
  return (b + std::sqrt(b * b - (n * n - 1) * c)) / (n * n - 1) - d;
}

FaceGrid point_focus_grid(int w, double size) {
  FaceGrid g;
  g.w = w;
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) g.lens.push_back(glm::dvec2(i, j) * (size / (w - 1)) - 0.5 * size);
  g.screen.assign(g.lens.size(), glm::dvec2(0.0));
  g.height.assign(g.lens.size(), 0.0);
  return g;
}
}  // namespace

TEST_F(Designer, NormalIntegrationReproducesThePlanoHyperbolicLens) {
  const double size = 20, focus = 60, n = 1.49;
  std::vector<double> errors, spots;
  for (const int w : {17, 33, 65}) {
    FaceGrid g = point_focus_grid(w, size);
    refine_heights(g, focus, n, 1e-12, 50);
    const std::size_t centre = std::size_t(w / 2) * w + w / 2;
    const double d = g.height[centre] + focus;
    double worst = 0;
    for (std::size_t v = 0; v < g.lens.size(); ++v)
      worst = std::max(worst, std::abs(g.height[v] - g.height[centre] - hyperbola_sag(glm::length(g.lens[v]), d, n)));
    errors.push_back(worst);
    // The engine with normals of the integrated surface itself (not the
    // prescribed ones, which would focus exactly by construction).
    Mesh m = face_mesh(g);
    m.normals = smooth_normals(m.positions, m.triangles);
    Scene s = straight_down_scene(5.0, focus, 2.0, 256);
    s.object.ior = n;
    const HdrImage img = render(s, shared(m));
    double flux = 0, moment = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const glm::dvec2 p = pixel_centre(s.screen, img.width, img.height, x, y);
        flux += img.at(x, y), moment += img.at(x, y) * glm::dot(p, p);
      }
    spots.push_back(std::sqrt(moment / flux));
    std::printf("w = %d: largest height error %.3e mm, rms spot radius %.4f mm\n", w, worst, spots.back());
  }
  EXPECT_GT(errors[0] / errors[1], 3.0) << "second order in the grid spacing";
  EXPECT_GT(errors[1] / errors[2], 3.0) << "second order in the grid spacing";
  EXPECT_LT(errors[2], 1e-3);
  EXPECT_LT(spots[1], spots[0]);
  EXPECT_LT(spots[2], spots[1]);
}

TEST_F(Designer, ThePicturesTopLeftLightsTheScreensTopLeft) {
  // Every figure of verify.cpp compares with target_irradiance(), the
  // designer's own masses: a flip or a transpose in turning the picture into
  // masses could not show there. Here the picture is written row by row
  // (row 0 the top) and the light is found on a screen the test places
  // itself (up +y, right +x, seen from above). The bright patch is the left
  // half of the top quarter, wider than tall, so that a transpose moves it too.
  const int n = 32;
  const double eps = 1e-2, w = 100;
  Image target{n, n, std::vector<float>(std::size_t(n) * n, 0.0f)};
  for (int row = 0; row < n / 4; ++row)
    for (int col = 0; col < n / 2; ++col) target.pixels[std::size_t(row) * n + col] = 0.8f;
  DesignOptions o = options(n);
  o.black_floor = eps;
  o.size = w;
  const Design d = design_face(target, o);
  Scene s = straight_down_scene(d.report.flat_offset, o.focus, w, 4 * n);
  const HdrImage img = render(s, shared(d.face));
  glm::dvec2 moment(0.0);
  double flux = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      flux += img.at(x, y);
      moment += double(img.at(x, y)) * pixel_centre(s.screen, img.width, img.height, x, y);
    }
  ASSERT_GT(flux, 0);
  const glm::dvec2 centroid = moment / flux;
  // The patch (area a, centre c) holds the share q of the light; the floor
  // the rest, spread evenly over the rest of the screen, whose centre is
  // -a c / (1 - a) (the whole screen's centre is 0).
  const double a = 1.0 / 8, q = a / (a + eps * (1 - a));
  const glm::dvec2 c(-w / 4, 3 * w / 8);
  const glm::dvec2 expected = c * (q - (1 - q) * a / (1 - a));
  std::printf("top-left patch: light's centroid (%.2f, %.2f) mm, expected (%.2f, %.2f)\n", centroid.x, centroid.y,
              expected.x, expected.y);
  EXPECT_NEAR(centroid.x, expected.x, w / n) << "within a cell";
  EXPECT_NEAR(centroid.y, expected.y, w / n) << "within a cell";
}

TEST_F(Designer, ATransportThatDidNotConvergeIsFlaggedAsItsRenderShows) {
  // One bright pixel at a black floor of 10^-6: the transport stalls with
  // most of the light in the wrong place. The flag is held to the engine's
  // render (the light that lands, not the transport's own residual), and
  // an ordinary picture is held to the same both ways.
  const int n = 32;
  Image dot{n, n, std::vector<float>(std::size_t(n) * n, 0.0f)};
  dot.pixels[std::size_t(10) * n + 10] = 1.0f;
  DesignOptions o;
  o.resolution = n;
  o.black_floor = 1e-6;
  const Design bad = design_face(dot, o);
  const Verification bad_render = verify_with_engine(bad);
  std::printf("one pixel: residual %.3f, engine relative L1 %.1f%%\n", bad.report.transport_residual,
              100 * bad_render.relative_l1);
  EXPECT_GT(bad_render.relative_l1, kMaxTransportResidual) << "the render itself is far from the picture";
  EXPECT_FALSE(bad.report.converged);
  EXPECT_NE(convergence_failure(bad.report).find("did not converge"), std::string::npos) << convergence_failure(bad.report);

  o.black_floor = 1e-2;
  const Design good = design_face(picture(n, smooth_blobs), o);
  EXPECT_LT(verify_with_engine(good).relative_l1, kMaxTransportResidual);
  EXPECT_TRUE(good.report.converged);
  EXPECT_TRUE(good.report.snell_settled) << good.report.snell_passes << " passes, last change " << good.report.snell_change;
  EXPECT_EQ(convergence_failure(good.report), "");
  // Cut off after one exact-Snell pass with a tolerance no pass meets.
  o.max_snell_passes = 1;
  o.height_tolerance = 1e-12;
  const Design cut = design_face(picture(n, smooth_blobs), o);
  EXPECT_FALSE(cut.report.snell_settled);
  EXPECT_NE(convergence_failure(cut.report).find("did not settle"), std::string::npos) << convergence_failure(cut.report);
}

TEST(DesignFace, IterationCountsAndTolerancesOutOfRangeAreRefusedByName) {
  const Image flat{8, 8, std::vector<float>(64, 0.5f)};
  const auto refused = [&](const std::function<void(DesignOptions&)>& set) {
    DesignOptions o;
    o.resolution = 8;
    set(o);
    return refusal<std::invalid_argument>([&] { design_face(flat, o); });
  };
  EXPECT_EQ(refused([](DesignOptions&) {}), "accepted");
  EXPECT_NE(refused([](DesignOptions& o) { o.homotopy_steps = 1000000; }).find("homotopy-steps"), std::string::npos);
  EXPECT_NE(refused([](DesignOptions& o) { o.max_iterations = 0; }).find("max-iterations"), std::string::npos);
  EXPECT_NE(refused([](DesignOptions& o) { o.max_iterations = 1 << 30; }).find("max-iterations"), std::string::npos);
  EXPECT_NE(refused([](DesignOptions& o) { o.max_snell_passes = 1000; }).find("max-snell-passes"), std::string::npos);
  for (const double bad : {0.0, -1.0, double(NAN), double(INFINITY)})
    EXPECT_NE(refused([&](DesignOptions& o) { o.height_tolerance = bad; }).find("height-tolerance"), std::string::npos)
        << bad;
}

TEST(DesignFace, APictureWithANanOrAnInfinityIsRefusedByItsPixel) {
  // Handed to design_face directly (the loader refuses them on its own): a
  // NaN once gave a flat face, an infinity "all black".
  for (const float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    Image target{8, 8, std::vector<float>(64, 0.5f)};
    target.pixels[3 * 8 + 5] = bad;
    DesignOptions o;
    o.resolution = 8;
    EXPECT_THROW(design_face(target, o), TargetError);
    const std::string why = refusal<TargetError>([&] { design_face(target, o); });
    EXPECT_NE(why.find("pixel (5, 3)"), std::string::npos) << why;
  }
}

TEST_F(Designer, EngineFluxEqualsTheEnteringFluxWithoutFresnel) {
  const Design d = design_face(picture(64, smooth_blobs), options(64));
  Scene s = design_scene(d, "designed", 512);
  s.render.fresnel = false;
  FluxSummary expected;
  ASSERT_TRUE(frame_screen(s, d.face, &expected));  // a screen that catches every triangle
  const HdrImage img = render(s, shared(d.face));
  const double entering = d.options.size * d.options.size;  // the face's footprint, E0 = 1
  EXPECT_NEAR(total_flux(img, s.screen) / entering, 1.0, 1e-4);
}

TEST_F(Designer, SymmetricTargetGivesSymmetricHeightsAndTheSameDesignTwice) {
  for (const bool regular : {false, true}) {
    DesignOptions o = options(64);
    o.resample = regular;
    const Design d = design_face(picture(64, smooth_blobs), o);
    const int w = d.grid.w;
    double worst = 0;
    for (int j = 0; j < w; ++j)
      for (int i = 0; i < w; ++i)
        worst = std::max(worst, std::abs(d.grid.height[std::size_t(j) * w + i] -
                                         d.grid.height[std::size_t(j) * w + w - 1 - i]));
    EXPECT_LT(worst, 1e-9 * d.options.size) << (regular ? "regular grid" : "warped grid");
    const Design again = design_face(picture(64, smooth_blobs), o);
    EXPECT_EQ(again.grid.height, d.grid.height) << "deterministic";
  }
}

TEST_F(Designer, DoublingTheFocusHalvesTheRelief) {
  DesignOptions o = options(64);
  const Design near = design_face(picture(64, smooth_blobs), o);
  o.focus *= 2;
  const Design far = design_face(picture(64, smooth_blobs), o);
  EXPECT_NEAR(near.report.relief / far.report.relief, 2.0, 0.04);
}

TEST_F(Designer, SolidIsWatertightAndThickEnough) {
  DesignOptions o = options(32);
  o.min_thickness = 3;
  const Design d = design_face(picture(32, smooth_blobs), o);
  const Mesh solid = solid_mesh(d.grid, d.report.flat_offset);
  std::map<std::pair<unsigned, unsigned>, int> directed;
  for (const auto& t : solid.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge used twice in the same direction";
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "edge without a twin: not closed";
  }
  EXPECT_GT(mesh_volume(solid), 0);
  float top = -1e30f, highest_face = -1e30f;
  for (const auto& p : solid.positions) top = std::max(top, p.z);
  for (double h : d.grid.height) highest_face = std::max(highest_face, float(h));
  EXPECT_GE(top - highest_face, 3 - 1e-4);
}

TEST(DesignTarget, DecodesSrgbKeepsLinearFloatsAndBoxFiltersExactly) {
  const auto dir = std::filesystem::temp_directory_path() / "causticd_design_target";
  std::filesystem::create_directories(dir);
  // 8-bit PNG: sRGB code 188 is linear 0.5 (IEC 61966-2-1: ((188/255 + 0.055) / 1.055)^2.4).
  Rgba8Image png{4, 4, std::vector<std::uint8_t>(4 * 4 * 4, 188)};
  write_png(png, dir / "grey.png");
  const double expected = std::pow((188 / 255.0 + 0.055) / 1.055, 2.4);
  const Image grey = load_target(dir / "grey.png");
  ASSERT_EQ(grey.pixels.size(), 16u);
  for (float v : grey.pixels) EXPECT_NEAR(v, expected, 1e-6);
  // Float EXR: already linear, read as it is.
  HdrImage exr{6, 4, std::vector<float>(24)};
  for (int p = 0; p < 24; ++p) exr.pixels[p] = 0.25f * (p % 6);
  write_exr(exr, dir / "ramp.exr");
  const Image loaded = load_target(dir / "ramp.exr");
  EXPECT_EQ(loaded.pixels, exr.pixels);
  // Centre square crop (columns 1..4 of 6), then 4 -> 2 cells: means of 2x2 blocks.
  const Image cells = box_resample_square(loaded, 2);
  ASSERT_EQ(cells.width, 2);
  EXPECT_FLOAT_EQ(cells.at(0, 0), 0.25f * 1.5f);
  EXPECT_FLOAT_EQ(cells.at(1, 1), 0.25f * 3.5f);
  // An n x n picture comes back unchanged at n.
  EXPECT_EQ(box_resample_square(box_resample_square(loaded, 4), 4).pixels, box_resample_square(loaded, 4).pixels);
  std::filesystem::remove_all(dir);
}

TEST(DesignTarget, WhatIsNoPictureFileOrClaimsAHugeOneIsRefusedBeforeItsReader) {
  const auto dir = std::filesystem::temp_directory_path() / "causticd_design_target_bad";
  std::filesystem::create_directories(dir);
  const auto refused = [](const std::filesystem::path& file) {
    return caustic::testing::refusal<TargetError>([&] { load_target_rgb(file); });
  };
  // A device, a folder and a pipe: read, or waited on, without end.
  EXPECT_NE(refused("/dev/zero").find("is not a regular file"), std::string::npos) << refused("/dev/zero");
  EXPECT_NE(refused(dir).find("is not a regular file"), std::string::npos);
  // A 13-byte GIF whose screen claims 65535 x 65535: its reader made the
  // canvas on open and threw out of it (the process aborted).
  for (const int side : {65535, 40000}) {
    std::ofstream out(dir / "huge.gif", std::ios::binary);
    const char head[] = {'G', 'I', 'F', '8', '9', 'a', char(side & 255), char(side >> 8), char(side & 255),
                         char(side >> 8), 0, 0, 0};
    out.write(head, sizeof head);
    out.close();
    EXPECT_NE(refused(dir / "huge.gif").find("pixels is too large"), std::string::npos) << refused(dir / "huge.gif");
  }
  std::filesystem::remove_all(dir);
}
