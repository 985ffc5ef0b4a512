// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/calibrate.hpp"

#include "caustic/engine.hpp"
#include "caustic/exposure.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace caustic {

std::pair<int, int> calibration_size(const Scene& scene, const CalibrateOptions& options) {
  const int f = options.compare_factor;
  const double longer = std::max(scene.render.width, scene.render.height);
  auto side = [&](int pixels) {
    return std::max(f, static_cast<int>(std::lround(options.max_side * pixels / longer / f)) * f);
  };
  return {side(scene.render.width), side(scene.render.height)};
}

Calibration calibrate(const Scene& scene, const MeshLevels& levels, Engine& engine, const std::string& renderer,
                      const CalibrateOptions& options) {
  auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  Scene truth = scene;
  std::tie(truth.render.width, truth.render.height) = calibration_size(scene, options);
  truth.render.intensity = IntensityMode::energy;
  truth.render.fresnel = true;
  truth.light.point_model = PointModel::exact;
  truth.render.mesh_resolution = 0;

  Calibration out;
  out.fingerprint = scene_fingerprint(scene, *levels.source);
  out.reference_photons = options.photons;
  out.width = truth.render.width;
  out.height = truth.render.height;
  out.compare_factor = options.compare_factor;
  out.renderer = renderer;

  ReferenceOptions ro;
  ro.photons = options.photons;
  ro.seed = options.seed;
  const ReferenceResult ref = trace_reference(truth, *levels.source, ro);
  const HdrImage reference = box_down(ref.image, options.compare_factor);
  char line[200];
  std::snprintf(line, sizeof line, "reference: %llu photons in %.1f s", static_cast<unsigned long long>(ref.photons),
                ref.seconds);
  say(line);

  // What a visitor sees: the engine's full model at the streamed size, the
  // yardstick for facets (the reference is too noisy there without a box
  // filter, which would blur them away).
  Scene streamed = truth;
  streamed.render.width = scene.render.width;
  streamed.render.height = scene.render.height;
  HdrImage full;
  double streamed_exposure = 1;
  if (options.streamed) {
    engine.set_scene(streamed, levels.source);
    engine.render();
    full = engine.read_hdr();
    streamed_exposure = exposure::settled_exposure(scene.post, full);
    out.streamed_width = streamed.render.width;
    out.streamed_height = streamed.render.height;
  }

  std::vector<PointModel> models{PointModel::exact};
  if (scene.light.type == LightType::point) models.push_back(PointModel::approximate);
  // A solid's multipass method trades light-grid rays for error; a slab has one grid, its mesh (0 here).
  std::vector<int> grids{0};
  if (scene.object.shape == Shape::solid) {
    grids.clear();
    for (int g : kCalibratedLightGrids)
      if (g < scene.render.light_grid) grids.push_back(g);
    grids.push_back(scene.render.light_grid);
  }
  for (int resolution : levels.resolutions())
    for (int grid : grids)
      for (PointModel model : models)
        for (bool fresnel : {true, false}) {
          Scene s = truth;
          s.render.intensity = scene.render.intensity;
          s.render.mesh_resolution = resolution;
          s.light.point_model = model;
          s.render.fresnel = fresnel;
          if (grid > 0) s.render.light_grid = grid;
          std::vector<double> ray_ms;
          for (int f = 0; f < options.frames + 1; ++f) {
            // A new handle: a full frame. Placed as the stream places it.
            engine.set_scene(s, std::make_shared<const Mesh>(*levels.at(resolution)), false, levels.bounds);
            engine.render();
            if (f > 0) ray_ms.push_back(engine.stats().ray_ms);
          }
          std::sort(ray_ms.begin(), ray_ms.end());
          const ImageError err = compare(box_down(engine.read_hdr(), options.compare_factor), reference,
                                         exposure::settled_exposure(scene.post, reference), scene.post.gamma);
          CalibrationEntry e;
          e.config = {resolution, model, fresnel, grid};
          e.vertices = levels.vertices(resolution);
          e.relative_l1 = err.relative_l1;
          e.relative_rmse = err.relative_rmse;
          e.ssim = err.ssim;
          e.ray_ms = ray_ms[ray_ms.size() / 2];
          if (options.streamed) {
            Scene at = s;
            at.render.width = streamed.render.width;
            at.render.height = streamed.render.height;
            engine.set_scene(at, levels.at(resolution), false, levels.bounds);
            engine.render();
            const ImageError seen = compare(engine.read_hdr(), full, streamed_exposure, scene.post.gamma);
            e.streamed_l1 = seen.relative_l1;
            e.streamed_ssim = seen.ssim;
          }
          out.entries.push_back(e);
          std::snprintf(line, sizeof line,
                        "mesh %-6s%s %-11s fresnel %-3s  %7.1f ms  L1 %.4f  SSIM %.4f  streamed L1 %.4f SSIM %.4f",
                        resolution ? (std::to_string(resolution) + "^2").c_str() : "loaded",
                        grid ? (" light grid " + std::to_string(grid) + "^2").c_str() : "",
                        point_model_name(model), fresnel ? "on" : "off", e.ray_ms,
                        e.relative_l1, e.ssim, e.streamed_l1.value_or(0), e.streamed_ssim.value_or(1));
          say(line);
        }
  return out;
}

}  // namespace caustic
