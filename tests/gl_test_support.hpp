// SPDX-License-Identifier: LGPL-2.1-or-later
// Shared set-up for tests that render: one headless GL context per test
// process, scenes built in code, and image statistics.
#pragma once

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/receivers.hpp"
#include "caustic/surfaces.hpp"
#include "caustic/vertex_rays.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace caustic::testing {

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!context_) context_ = std::make_unique<GlContext>(egl_platform_from_environment());
  }
  void SetUp() override { engine_ = std::make_unique<Engine>(); }
  void TearDown() override { engine_.reset(); }

  HdrImage render(const Scene& scene, std::shared_ptr<const Mesh> mesh) {
    engine_->set_scene(scene, std::move(mesh));
    engine_->render();
    return engine_->read_hdr();
  }
  RgbHdrImage render_rgb(const Scene& scene, std::shared_ptr<const Mesh> mesh) {
    engine_->set_scene(scene, std::move(mesh));
    engine_->render();
    return engine_->read_hdr_rgb();
  }

  static inline std::unique_ptr<GlContext> context_;
  std::unique_ptr<Engine> engine_;
};

/// A directional light straight down (-z) on an object whose flat face
/// (normal +z) sits at z = flat_offset, screen facing up at z = -distance.
inline Scene straight_down_scene(double flat_offset, double distance, double screen_size, int pixels) {
  Scene s;
  s.mesh = "generated";
  s.object.flat_face_offset = flat_offset;
  s.light.direction = {0, 0, -1};
  s.screen.center = {0, 0, -distance};
  s.screen.normal = {0, 0, 1};
  s.screen.up = {0, 1, 0};
  s.screen.width = s.screen.height = screen_size;
  s.render.width = s.render.height = pixels;
  s.render.fresnel = false;
  s.post.exposure_mode = ExposureMode::manual;  // tests read the curve at the exposure they write
  return s;
}

// A receiver rectangle (normal and up made unit).
inline ScreenParams rectangle(glm::dvec3 centre, glm::dvec3 normal, glm::dvec3 up, double width, double height) {
  ScreenParams r;
  r.center = centre;
  r.normal = glm::normalize(normal);
  r.up = glm::normalize(up);
  r.width = width;
  r.height = height;
  return r;
}

inline std::shared_ptr<const Mesh> shared(Mesh m) { return std::make_shared<const Mesh>(std::move(m)); }

/// A 20 x 20 mm flat slab, its flat face at z = 1; 0.31 mm between rays.
inline std::shared_ptr<const Mesh> fine_slab() {
  static const auto mesh = shared(grid_mesh(flat_face(10), 65, 65));
  return mesh;
}

/// A shaped receiver 30 mm under fine_slab()'s straight-down light (Fresnel
/// off) with a 40 x 40 mm floor 50 mm down under both, the screen parked
/// 300 mm aside where no light goes: the receivers' oracles' set-up.
inline Scene over_a_floor(int pixels, const ScreenParams& shape) {
  Scene s = straight_down_scene(1, 50, 10, pixels);
  s.screen.center = {0, 300, -50};
  ScreenParams floor;
  floor.center = {0, 0, -50};
  floor.width = floor.height = 40;
  s.receivers = {shape, floor};
  return s;
}

/// Screen position (right, up) of a pixel centre: row 0 is the top.
inline glm::dvec2 pixel_centre(const ScreenParams& screen, int width, int height, int x, int y) {
  return {(x + 0.5) / width * screen.width - 0.5 * screen.width,
          0.5 * screen.height - (y + 0.5) / height * screen.height};
}

inline double total_flux(const HdrImage& img, const ScreenParams& screen) {
  double sum = 0;
  for (float v : img.pixels) sum += v;
  return sum * (screen.width / img.width) * (screen.height / img.height);
}

/// The sum of the pixels of one tile of an atlas (caustic/receivers.hpp).
inline double tile_sum(const HdrImage& img, const AtlasTile& t) {
  double sum = 0;
  for (int y = t.y; y < t.y + t.height; ++y)
    for (int x = t.x; x < t.x + t.width; ++x) sum += img.pixels[static_cast<std::size_t>(y) * img.width + x];
  return sum;
}

/// Sum of |a - b| over the sum of |b|: an image against its reference.
inline double relative_l1(const HdrImage& a, const HdrImage& b) {
  double diff = 0, sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    diff += std::abs(a.pixels[i] - b.pixels[i]);
    sum += std::abs(b.pixels[i]);
  }
  return diff / sum;
}

inline bool all_finite(const HdrImage& img) {
  for (float v : img.pixels)
    if (!std::isfinite(v) || v < 0) return false;
  return true;
}

inline // Sizes the screen rectangle around every projected vertex, with a margin,
// so that no triangle is clipped and the whole flux must land on the image.
bool frame_screen(Scene& s, const Mesh& mesh, FluxSummary* expected) {
  const Placement placement = place_object(s.object, mesh);
  *expected = summarize_flux(s, mesh, placement);
  if (expected->valid_triangles == 0) return false;
  const glm::dvec2 lo = expected->screen_min, hi = expected->screen_max;
  const double size = 1.1 * std::max(hi.x - lo.x, hi.y - lo.y) + 1e-3;
  const glm::dvec2 mid = 0.5 * (lo + hi);
  s.screen.center += mid.x * screen_right(s.screen) + mid.y * s.screen.up;
  s.screen.width = s.screen.height = size;
  *expected = summarize_flux(s, mesh, placement);
  return true;
}

/// Every scene the build ships (the designed ones only when it made them),
/// for tests over all of them, and their names as gtest allows them.
inline const std::vector<std::string> kShippedScenes{"slab",       "wavy",       "cylinder",         "lens",  "prism", "biconvex", "room",
                                                     "design-cat", "design-astronaut", "design-logo", "design-text"};
inline std::string scene_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

}  // namespace caustic::testing
