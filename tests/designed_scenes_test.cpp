// SPDX-License-Identifier: LGPL-2.1-or-later
// The built-in designed scenes (assets/designs.cmake) as the build wrote
// them: each scene loads with its mesh, and a fresh engine render of the
// files on disk forms the target picture. The SSIM is recomputed here from
// the written target, scene and mesh rather than taken from the designer's
// report, so a scene or mesh that went wrong after the design would show.
#include "caustic/design_colour.hpp"
#include "caustic/design_target.hpp"
#include "caustic/design_verify.hpp"
#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kAssets = CAUSTIC_ASSET_DIR;

std::vector<std::string> designed_ids() {
  std::vector<std::string> ids;
  std::stringstream list(CAUSTIC_DESIGNED_SCENES);
  for (std::string id; std::getline(list, id, ',');)
    if (!id.empty()) ids.push_back(id);
  return ids;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// The screen's relative irradiance the design aims at (docs/design.md, step
// 1): densities max(Y / max Y, floor) on n x n cells, scaled to mean 1; for
// a colour design Y is the brightest channel (docs/design.md, "Colour").
caustic::HdrImage target_irradiance(const caustic::HdrImage& picture, int n, double floor) {
  caustic::HdrImage cells = caustic::design::box_resample_square(picture, n);
  const float brightest = *std::max_element(cells.pixels.begin(), cells.pixels.end());
  double sum = 0;
  for (float& v : cells.pixels) sum += v = static_cast<float>(std::max(double(v) / brightest, floor));
  const double mean = sum / double(cells.pixels.size());
  for (float& v : cells.pixels) v = static_cast<float>(v / mean);
  return cells;
}

class DesignedScene : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST(DesignedScenes, TheBuildMadeTheDrawnOnesAndThePhotographsWhenGiven) {
  const auto ids = designed_ids();
  for (const char* id : {"design-logo", "design-text"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
  if (CAUSTIC_DESIGN_PHOTOS) {
    for (const char* id : {"design-cat", "design-astronaut", "design-coffee"})
      EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
  }
  for (const auto& id : ids) {
    EXPECT_TRUE(fs::is_regular_file(kAssets / "scenes" / (id + ".json"))) << id;
    EXPECT_TRUE(fs::is_regular_file(kAssets / "scenes" / (id + ".calibration.json"))) << id;
    // The gallery loads every other *.json in scenes/: nothing else of a design may be there.
    EXPECT_FALSE(fs::exists(kAssets / "scenes" / (id + ".report.json"))) << id;
  }
}

TEST_P(DesignedScene, LoadsAndItsEngineRenderFormsTheTarget) {
  const std::string id = GetParam();
  const caustic::Scene scene = caustic::load_scene(kAssets / "scenes" / (id + ".json"));
  EXPECT_FALSE(scene.name.empty());
  EXPECT_NE(scene.name, "Designed caustic") << "the build names every designed scene";
  EXPECT_FALSE(scene.description.empty());
  const auto mesh = std::make_shared<const caustic::Mesh>(caustic::load_obj(scene.mesh_path()));

  const nlohmann::json report = read_json(kAssets / "designs" / (id + ".report.json"));
  const int n = report["resolution"];
  EXPECT_EQ(report["tir_vertices"], 0);
  EXPECT_GE(report["engine"]["ssim"].get<double>(), 0.85);

  // As the designer checks it: Fresnel off, so that all the light that enters
  // lands and the render is comparable with the target's mean of 1; one pixel per cell.
  caustic::Scene check = scene;
  check.render.fresnel = false;
  check.render.width = check.render.height = n;
  caustic::GlContext context(caustic::egl_platform_from_environment());
  caustic::Engine engine;
  engine.set_scene(check, mesh);
  engine.render();
  const bool colour = report.value("colour", false);
  const fs::path picture = kAssets / "designs" / (id + ".target.png");
  const double floor = report["black_floor"].get<double>();
  // A colour design's shape is judged by its brightest channel, then each
  // channel against the picture's colour at the same scale.
  const caustic::RgbHdrImage rgb = colour ? engine.read_hdr_rgb() : caustic::RgbHdrImage{};
  const caustic::HdrImage render = colour ? caustic::design::brightest_channel(rgb) : engine.read_hdr();
  ASSERT_EQ(render.width, n);
  EXPECT_EQ(engine.stats().colour, colour) << id;

  const caustic::HdrImage target =
      colour ? target_irradiance(caustic::design::brightest_channel(caustic::design::load_target_rgb(picture)), n, floor)
             : target_irradiance(caustic::design::load_target(picture), n, floor);
  if (colour) {
    const caustic::RgbHdrImage cells = caustic::design::box_resample_square(caustic::design::load_target_rgb(picture), n);
    double diff[3] = {0, 0, 0}, total[3] = {0, 0, 0};
    for (std::size_t p = 0; p < target.pixels.size(); ++p) {
      const float* c = &cells.pixels[3 * p];
      const float m = std::max({c[0], c[1], c[2]});
      for (int k = 0; k < 3; ++k) {
        const double wanted = target.pixels[p] * (m > 0 ? c[k] / m : 1.0);
        diff[k] += std::abs(rgb.pixels[3 * p + k] - wanted);
        total[k] += wanted;
      }
    }
    for (int k = 0; k < 3; ++k) {
      RecordProperty("relative_l1_channel_" + std::to_string(k), std::to_string(diff[k] / total[k]));
      EXPECT_LT(diff[k] / total[k], 0.15) << id << ": relative L1 of channel " << k;
    }
  }
  const double ssim = caustic::tonemapped_ssim(render, target, caustic::design::target_exposure(target), 2.2);
  double diff = 0, total = 0;
  for (std::size_t p = 0; p < target.pixels.size(); ++p) {
    diff += std::abs(double(render.pixels[p]) - target.pixels[p]);
    total += target.pixels[p];
  }
  RecordProperty("ssim", std::to_string(ssim));
  RecordProperty("relative_l1", std::to_string(diff / total));
  EXPECT_GE(ssim, 0.85) << id;
  EXPECT_LT(diff / total, 0.05) << id << ": relative L1";
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, DesignedScene, ::testing::ValuesIn(designed_ids()),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });
