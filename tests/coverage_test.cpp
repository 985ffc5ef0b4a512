// SPDX-License-Identifier: LGPL-2.1-or-later
// The CPU's accumulated-area coverage (src/engine/coverage.hpp) against an
// independent oracle: each triangle clipped to each pixel's square
// (Sutherland-Hodgman) and the clipped polygon's area by the shoelace
// formula. Random triangles, thin ones, both windings, past every edge of
// the image.
#include "coverage.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using caustic::CoverageRaster;

namespace {

using Polygon = std::vector<glm::dvec2>;

// `poly` cut to the half-plane where inside(p) >= 0 (inside is affine in p).
template <typename F>
Polygon clip(const Polygon& poly, F inside) {
  Polygon out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
    const double dp = inside(p), dq = inside(q);
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  return out;
}

double area(const Polygon& poly) {
  double twice = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
    twice += p.x * q.y - p.y * q.x;
  }
  return std::abs(0.5 * twice);
}

// The area of triangle abc within pixel (i, j).
double covered(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, int i, int j) {
  Polygon p{a, b, c};
  p = clip(p, [&](glm::dvec2 v) { return v.x - i; });
  p = clip(p, [&](glm::dvec2 v) { return i + 1 - v.x; });
  p = clip(p, [&](glm::dvec2 v) { return v.y - j; });
  p = clip(p, [&](glm::dvec2 v) { return j + 1 - v.y; });
  return p.size() < 3 ? 0.0 : area(p);
}

}  // namespace

TEST(Coverage, EachPixelGetsTheAreaTheTriangleCoversInIt) {
  constexpr int kWidth = 37, kHeight = 29;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-12.0, kWidth + 12.0), y(-12.0, kHeight + 12.0), unit(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    glm::dvec2 a(x(rng), y(rng)), b(x(rng), y(rng)), c(x(rng), y(rng));
    if (trial % 4 == 1) c = a + (b - a) * unit(rng) + glm::dvec2(0.3, -0.2) * unit(rng);  // a sliver
    if (trial % 4 == 2) c = glm::dvec2(a.x + 0.4 * unit(rng), b.y);                        // within a column
    const double value = 0.5 + unit(rng);
    CoverageRaster raster;
    raster.reset(kWidth, kHeight, 1);
    raster.triangle(a, b, c, glm::dvec3(value));
    const std::vector<float>& image = raster.resolve();
    for (int j = 0; j < kHeight; ++j)
      for (int i = 0; i < kWidth; ++i)
        ASSERT_NEAR(image[static_cast<std::size_t>(j) * kWidth + i], value * covered(a, b, c, i, j), 1e-6 * value)
            << "trial " << trial << " pixel " << i << "," << j;
  }
}

TEST(Coverage, TrianglesAddUpAndChannelsKeepTheirValues) {
  const glm::dvec2 a(1.2, 0.5), b(9.7, 2.25), c(4.1, 8.8), d(10.5, 7.5);
  CoverageRaster raster;
  raster.reset(12, 10, 3);
  raster.triangle(a, b, c, {1.0, 2.0, 0.5});
  raster.triangle(c, b, d, {3.0, 0.0, 1.0});  // the other winding, sharing an edge
  raster.triangle(a, c, b, {0.25, 0.25, 0.25});  // on top of the first: a fold
  const std::vector<float>& image = raster.resolve();
  double total[3] = {0, 0, 0};
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 12; ++i) {
      const double first = covered(a, b, c, i, j), second = covered(c, b, d, i, j);
      const double expected[3] = {1.25 * first + 3.0 * second, 2.25 * first, 0.75 * first + second};
      for (int k = 0; k < 3; ++k) {
        const float got = image[(static_cast<std::size_t>(j) * 12 + i) * 3 + k];
        EXPECT_NEAR(got, expected[k], 1e-6) << i << "," << j << " channel " << k;
        total[k] += got;
      }
    }
  const double abc = 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
  const double cbd = 0.5 * std::abs((b.x - c.x) * (d.y - c.y) - (b.y - c.y) * (d.x - c.x));
  EXPECT_NEAR(total[0], 1.25 * abc + 3.0 * cbd, 1e-5);
  EXPECT_NEAR(total[1], 2.25 * abc, 1e-5);
}

TEST(Coverage, APointFillsThePixelUnderItAndNothingOutsideCounts) {
  CoverageRaster raster;
  raster.reset(8, 6, 1);
  raster.point({3.5, 2.0}, glm::dvec3(7.0));
  raster.point({7.99, 5.99}, glm::dvec3(2.0));
  raster.point({8.0, 1.0}, glm::dvec3(100.0));   // past the right edge
  raster.point({-0.01, 1.0}, glm::dvec3(100.0));  // past the left
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  raster.point({nan, 1.0}, glm::dvec3(100.0));
  raster.triangle({0, 0}, {inf, 0}, {0, 3}, glm::dvec3(100.0));
  raster.triangle({0, 0}, {4, nan}, {0, 3}, glm::dvec3(100.0));
  raster.triangle({-20, -20}, {-10, -20}, {-20, -10}, glm::dvec3(100.0));  // wholly outside
  raster.triangle({20, 20}, {30, 20}, {20, 30}, glm::dvec3(100.0));
  const std::vector<float>& image = raster.resolve();
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 8; ++i) {
      const double expected = i == 3 && j == 2 ? 7.0 : i == 7 && j == 5 ? 2.0 : 0.0;
      EXPECT_EQ(image[static_cast<std::size_t>(j) * 8 + i], expected) << i << "," << j;
    }
}

namespace {

// Two triangles a cell of an nx x ny grid of vertices (row-major), one of each winding.
std::vector<glm::uvec3> grid_triangles(int nx, int ny) {
  std::vector<glm::uvec3> triangles;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const unsigned v = j * nx + i, row = static_cast<unsigned>(nx);
      triangles.push_back({v, v + 1, v + row + 1});
      triangles.push_back({v, v + row + 1, v + row});
    }
  return triangles;
}

}  // namespace

TEST(Coverage, AMeshWalksEachSharedEdgeOnceAndCoversAsItsTriangles) {
  // A 6 x 5 grid of vertices jittered hard enough to fold, with triangles of
  // each winding, some left out (their neighbours' shared edges then stand
  // alone), four images on one grid: its edge table is built once.
  constexpr int kWidth = 23, kHeight = 19, kNx = 6, kNy = 5;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-2.5, 2.5), unit(0.0, 1.0);
  const std::vector<glm::uvec3> triangles = grid_triangles(kNx, kNy);
  CoverageRaster raster;
  for (int frame = 0; frame < 2; ++frame)
    for (int channels : {1, 3}) {
      std::vector<glm::dvec2> at(kNx * kNy);
      for (int j = 0; j < kNy; ++j)
        for (int i = 0; i < kNx; ++i) at[j * kNx + i] = {-3.0 + 5.5 * i + jitter(rng), -2.0 + 5.0 * j + jitter(rng)};
      std::vector<glm::dvec3> values(triangles.size());
      for (auto& v : values) v = unit(rng) < 0.15 ? glm::dvec3(0) : glm::dvec3(unit(rng), unit(rng), unit(rng));
      raster.reset(kWidth, kHeight, channels);
      raster.use_mesh(triangles);
      for (std::size_t t = 0; t < triangles.size(); ++t)
        if (values[t] != glm::dvec3(0)) {
          const glm::uvec3 c = triangles[t];
          raster.mesh_triangle(t, at[c.x], at[c.y], at[c.z], values[t]);
        }
      const std::vector<float>& image = raster.resolve();
      for (int j = 0; j < kHeight; ++j)
        for (int i = 0; i < kWidth; ++i)
          for (int k = 0; k < channels; ++k) {
            double expected = 0;
            for (std::size_t t = 0; t < triangles.size(); ++t) {
              const glm::uvec3 c = triangles[t];
              expected += values[t][k] * covered(at[c.x], at[c.y], at[c.z], i, j);
            }
            ASSERT_NEAR(image[(static_cast<std::size_t>(j) * kWidth + i) * channels + k], expected, 1e-5)
                << "frame " << frame << ", " << channels << " channels, pixel " << i << "," << j << " channel " << k;
          }
    }
}

TEST(Coverage, LayersAndFlushedPassesAddUpAsOneImage) {
  // Three passes over one grid at different positions (a wavelength each),
  // each pass's triangles dealt between two layers as two threads fill
  // them, a point and a loose triangle in each, flushed between passes and resolved once: the
  // image is every pass's coverage summed. The middle channel's values run
  // below 0 too (a spectral weight): its sums stand where they are negative.
  constexpr int kWidth = 21, kHeight = 17, kNx = 5, kNy = 4, kPasses = 3;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-2.0, 2.0), unit(0.0, 1.0);
  const std::vector<glm::uvec3> triangles = grid_triangles(kNx, kNy);
  CoverageRaster raster;
  raster.reset(kWidth, kHeight, 3);
  std::vector<double> expected(static_cast<std::size_t>(kWidth) * kHeight * 3, 0.0);
  for (int pass = 0; pass < kPasses; ++pass) {
    if (pass > 0) raster.flush();
    std::vector<glm::dvec2> at(kNx * kNy);
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) at[j * kNx + i] = {-2.0 + 5.5 * i + jitter(rng), -1.0 + 5.0 * j + jitter(rng)};
    raster.use_mesh(triangles, 2);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const glm::dvec3 value(unit(rng), unit(rng) - 0.7, unit(rng));
      const glm::uvec3 c = triangles[t];
      raster.mesh_triangle(t, at[c.x], at[c.y], at[c.z], value, static_cast<int>(t % 2));
      for (int j = 0; j < kHeight; ++j)
        for (int i = 0; i < kWidth; ++i)
          for (int k = 0; k < 3; ++k)
            expected[(static_cast<std::size_t>(j) * kWidth + i) * 3 + k] +=
                value[k] * covered(at[c.x], at[c.y], at[c.z], i, j);
    }
    // A piece cut from a triangle, beside the mesh's in a layer.
    const glm::dvec2 la(jitter(rng) + 10, jitter(rng) + 8), lb = la + glm::dvec2(6.5, 1.5), lc = la + glm::dvec2(2, 5.25);
    const glm::dvec3 loose(1.5, unit(rng), 0.25);
    raster.loose_triangle(la, lb, lc, loose, 1 - pass % 2);
    for (int j = 0; j < kHeight; ++j)
      for (int i = 0; i < kWidth; ++i)
        for (int k = 0; k < 3; ++k)
          expected[(static_cast<std::size_t>(j) * kWidth + i) * 3 + k] += loose[k] * covered(la, lb, lc, i, j);
    const glm::dvec3 point(0.5 + pass, 1.0, 2.0);
    raster.point({3.5 + 4 * pass, 7.25}, point, pass % 2);
    for (int k = 0; k < 3; ++k) expected[(7 * static_cast<std::size_t>(kWidth) + 3 + 4 * pass) * 3 + k] += point[k];
  }
  ASSERT_LT(*std::min_element(expected.begin(), expected.end()), -0.1);
  const std::vector<float>& image = raster.resolve();
  for (std::size_t n = 0; n < expected.size(); ++n) ASSERT_NEAR(image[n], expected[n], 1e-5) << "value " << n;
}

TEST(Coverage, ARasterReusedOverFramesAndMeshesKeepsNothingOfTheLast) {
  // Frames as the caustic pass makes them: contiguous shares of the
  // triangles in layers (a walk and a clear cover each layer's share of the
  // edges only), the last pass resolved without a flush, then the next frame
  // on the same grid, on another grid of another size, and back. Every frame
  // must hold its own triangles' coverage and nothing left from before.
  constexpr int kWidth = 19, kHeight = 17;
  struct Frame {
    int nx, ny, layers, channels;
    bool flush_first;
  };
  const Frame frames[] = {{6, 5, 2, 3, false}, {6, 5, 2, 3, true}, {4, 4, 3, 1, true},
                          {6, 5, 1, 3, false}, {6, 5, 2, 1, false}, {4, 4, 2, 3, false}};
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> jitter(-1.5, 1.5), unit(0.1, 1.0);
  CoverageRaster raster;
  for (std::size_t f = 0; f < std::size(frames); ++f) {
    const Frame& fr = frames[f];
    const std::vector<glm::uvec3> triangles = grid_triangles(fr.nx, fr.ny);
    std::vector<double> expected(static_cast<std::size_t>(kWidth) * kHeight * fr.channels, 0.0);
    raster.reset(kWidth, kHeight, fr.channels);
    for (int pass = 0; pass < (fr.flush_first ? 2 : 1); ++pass) {
      if (pass > 0) raster.flush();
      std::vector<glm::dvec2> at(static_cast<std::size_t>(fr.nx * fr.ny));
      const double sx = (kWidth - 2.0) / (fr.nx - 1), sy = (kHeight - 2.0) / (fr.ny - 1);
      for (int j = 0; j < fr.ny; ++j)
        for (int i = 0; i < fr.nx; ++i) at[j * fr.nx + i] = {1.0 + sx * i + jitter(rng), 1.0 + sy * j + jitter(rng)};
      raster.use_mesh(triangles, fr.layers);
      for (int layer = 0; layer < fr.layers; ++layer)
        for (std::size_t t = triangles.size() * layer / fr.layers; t < triangles.size() * (layer + 1) / fr.layers; ++t) {
          const glm::dvec3 value(unit(rng), unit(rng), unit(rng));
          const glm::uvec3 c = triangles[t];
          raster.mesh_triangle(t, at[c.x], at[c.y], at[c.z], value, layer);
          for (int j = 0; j < kHeight; ++j)
            for (int i = 0; i < kWidth; ++i)
              for (int k = 0; k < fr.channels; ++k)
                expected[(static_cast<std::size_t>(j) * kWidth + i) * fr.channels + k] +=
                    value[k] * covered(at[c.x], at[c.y], at[c.z], i, j);
        }
    }
    const std::vector<float>& image = raster.resolve();
    for (std::size_t n = 0; n < expected.size(); ++n)
      ASSERT_NEAR(image[n], expected[n], 1e-5) << "frame " << f << ", value " << n;
  }
}
