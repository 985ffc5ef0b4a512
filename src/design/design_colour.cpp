// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/design_colour.hpp"

#include "caustic/colour.hpp"
#include "caustic/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

namespace caustic::design {
namespace {

// The tint that turns the brightest channel into the cell's colour; white
// below `floor` (the design's black floor: a black cell gets almost no light,
// and white keeps the floor's faint glow neutral).
glm::vec3 cell_tint(const float* c, float floor) {
  const float m = std::max({c[0], c[1], c[2]});
  if (!(m > floor)) return glm::vec3(1.0f);
  return glm::clamp(glm::vec3(c[0], c[1], c[2]) / m, 0.0f, 1.0f);
}

float tint_floor(const Design& design, const RgbHdrImage& cells) {
  float peak = 0;
  for (float v : cells.pixels) peak = std::max(peak, v);
  return static_cast<float>(design.options.black_floor) * peak;
}

glm::dvec2 chromaticity(const float* c) {
  const auto xy = optics::chromaticity(optics::xyz(optics::Rgb{c[0], c[1], c[2]}));
  return {xy[0], xy[1]};
}

}  // namespace

Image brightest_channel(const RgbHdrImage& target) {
  Image out{target.width, target.height, std::vector<float>(target.pixels.size() / 3)};
  for (std::size_t i = 0; i < out.pixels.size(); ++i)
    out.pixels[i] = std::max({target.pixels[3 * i], target.pixels[3 * i + 1], target.pixels[3 * i + 2]});
  return out;
}

RgbHdrImage box_resample_square(const RgbHdrImage& image, int n) {
  RgbHdrImage out;
  for (int c = 0; c < 3; ++c) set_channel(out, c, box_resample_square(channel(image, c), n));
  return out;
}

void tint_face(Design& design, const RgbHdrImage& target) {
  const int n = design.n;
  const RgbHdrImage cells = box_resample_square(target, n);
  const double size = design.options.size;
  const float floor = tint_floor(design, cells);
  auto cell = [&](int i, int j) {
    return &cells.pixels[3 * (static_cast<std::size_t>(std::clamp(j, 0, n - 1)) * n + std::clamp(i, 0, n - 1))];
  };
  auto& colours = design.face.colours;
  colours.assign(design.face.positions.size(), glm::vec3(1.0f));
  for (std::size_t v = 0; v < design.grid.screen.size() && v < colours.size(); ++v) {
    // The vertex's screen point in cell units (x from the left, rows from
    // the top; cell centres at k + 1/2). A vertex sits on cell corners, so
    // the light around it is shared by up to four cells in proportion to
    // what the design sends each (its brightest channel): its tint is their
    // colours mixed by that light, bilinearly.
    const glm::dvec2 s = design.grid.screen[v] / size + 0.5;
    const double x = s.x * n - 0.5, y = (1.0 - s.y) * n - 0.5;
    const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
    const double fx = x - i, fy = y - j;
    glm::dvec3 mixed(0.0);
    double light = 0;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const float* c = cell(i + di, j + dj);
        const double w = (di ? fx : 1 - fx) * (dj ? fy : 1 - fy);
        mixed += w * glm::dvec3(c[0], c[1], c[2]);
        light += w * std::max({c[0], c[1], c[2]});
      }
    if (light > floor) colours[v] = glm::clamp(glm::vec3(mixed / light), 0.0f, 1.0f);
  }
}

ColourVerification verify_colour_with_engine(const Design& design, const RgbHdrImage& target) {
  const auto start = std::chrono::steady_clock::now();
  Scene s = design_scene(design, "designed", design.n);
  s.render.fresnel = false;
  Engine engine;
  engine.set_scene(s, std::make_shared<const Mesh>(design.face));
  engine.render();
  ColourVerification v;
  v.render = engine.read_hdr_rgb();
  const HdrImage wanted = target_irradiance(design);  // the brightest channel, at the design's scale
  v.brightest = compare_with_target(design, brightest_channel(v.render), target_exposure(wanted));
  // The colour the design aims at: the target's, scaled as its brightest channel was.
  const RgbHdrImage cells = box_resample_square(target, design.n);
  const std::size_t count = wanted.pixels.size();
  RgbHdrImage& aim = v.aim;
  aim = RgbHdrImage{design.n, design.n, std::vector<float>(3 * count)};
  const float floor = tint_floor(design, cells);
  for (std::size_t p = 0; p < count; ++p) {
    const glm::vec3 tint = cell_tint(&cells.pixels[3 * p], floor);
    for (int k = 0; k < 3; ++k) aim.pixels[3 * p + k] = wanted.pixels[p] * tint[k];
  }
  const HdrImage aim_y = luminance(aim);
  double mean_luminance = 0;
  for (float y : aim_y.pixels) mean_luminance += y / count;
  double diff[3] = {0, 0, 0}, total[3] = {0, 0, 0}, weighted = 0, weight = 0;
  for (std::size_t p = 0; p < count; ++p) {
    for (int k = 0; k < 3; ++k) {
      diff[k] += std::abs(double(v.render.pixels[3 * p + k]) - aim.pixels[3 * p + k]);
      total[k] += aim.pixels[3 * p + k];
    }
    if (aim_y.pixels[p] < 0.1 * mean_luminance) continue;
    weighted += aim_y.pixels[p] * glm::length(chromaticity(&v.render.pixels[3 * p]) - chromaticity(&aim.pixels[3 * p]));
    weight += aim_y.pixels[p];
  }
  for (int k = 0; k < 3; ++k) v.relative_l1[k] = total[k] > 0 ? diff[k] / total[k] : 0;
  v.chromaticity_error = weight > 0 ? weighted / weight : 0;
  v.brightest.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return v;
}

}  // namespace caustic::design
