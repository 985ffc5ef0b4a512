// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/design_verify.hpp"

#include "caustic/design_colour.hpp"

#include "caustic/engine.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

namespace caustic::design {
namespace {

// The scene the checks render: the design's own, Fresnel off and pixels = cells.
Scene check_scene(const Design& design) {
  Scene s = design_scene(design, "designed", design.n);
  s.render.fresnel = false;
  return s;
}

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

double target_exposure(const HdrImage& target) {
  std::vector<float> v = target.pixels;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(0.99 * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return std::clamp(std::log(10.0) / std::max(double(v[k]), 1e-9), 0.01, 10.0);
}

Scene design_scene(const Design& design, const std::string& mesh_file, int pixels) {
  const DesignOptions& o = design.options;
  Scene s;
  s.name = "Designed caustic";
  s.description = "A designed freeform face (" + std::to_string(design.n) + "^2 cells, n = " +
                  std::to_string(o.ior).substr(0, 4) + ") throwing its target picture on a screen " +
                  std::to_string(static_cast<int>(std::lround(o.focus))) + " mm below.";
  s.mesh = mesh_file;
  s.object.material = Material::refractive;
  s.object.ior = o.ior;
  s.object.flat_face_normal = {0, 0, 1};
  s.object.flat_face_offset = design.report.flat_offset;
  s.light.type = LightType::directional;
  s.light.direction = {0, 0, -1};
  s.screen.center = {0, 0, -o.focus};
  s.screen.normal = {0, 0, 1};
  s.screen.up = {0, 1, 0};
  s.screen.width = s.screen.height = o.size;
  s.screen.follow_light = true;  // a visitor who turns the light keeps the picture in view
  s.render.width = s.render.height = std::clamp(pixels, 16, 8192);
  s.render.fidelity = Fidelity::manual;
  s.render.fresnel = true;
  s.render.mesh_resolution = 0;
  // Shown with automatic exposure (the default); the glow starts where the
  // target's own exposure would put white.
  s.post.bloom_threshold = 4.0 / target_exposure(target_irradiance(design));
  s.post.bloom_strength = 0.1;
  return s;
}

Verification compare_with_target(const Design& design, const HdrImage& full_render, double exposure, int factor) {
  const HdrImage target = factor > 1 ? box_down(target_irradiance(design), factor) : target_irradiance(design);
  const HdrImage render = factor > 1 ? box_down(full_render, factor) : full_render;
  Verification v;
  double diff = 0, total = 0, black = 0, landed = 0, floor_light = 0;
  // Black pixels: at the floor (a mean over cells all at the floor, after box_down).
  const float floor_level = static_cast<float>(design.floor_mass * design.n * design.n * (1 + 1e-5));
  for (std::size_t p = 0; p < target.pixels.size(); ++p) {
    diff += std::abs(double(render.pixels[p]) - target.pixels[p]);
    total += target.pixels[p];
    landed += render.pixels[p];
    if (target.pixels[p] <= floor_level) black += render.pixels[p], floor_light += target.pixels[p];
  }
  v.relative_l1 = diff / total;
  v.leak = landed > 0 ? black / landed : 0;
  v.ideal_leak = floor_light / total;
  v.landed = landed / total;  // the target's mean is 1: its sum is the lens flux
  v.ssim = tonemapped_ssim(render, target, exposure, 2.2);
  v.render = full_render;
  return v;
}

Verification verify_with_engine(const Design& design) {
  const auto start = std::chrono::steady_clock::now();
  const Scene s = check_scene(design);
  Engine engine;
  engine.set_scene(s, std::make_shared<const Mesh>(design.face));
  engine.render();
  // A tinted face (a colour design) was shaped for its brightest channel.
  const HdrImage shaped = tinted(design.face) ? brightest_channel(engine.read_hdr_rgb()) : engine.read_hdr();
  Verification v = compare_with_target(design, shaped, target_exposure(target_irradiance(design)));
  v.seconds = since(start);
  return v;
}

Verification verify_with_reference(const Design& design, std::uint64_t photons) {
  const auto start = std::chrono::steady_clock::now();
  const Scene s = check_scene(design);
  ReferenceOptions ro;
  ro.photons = photons;
  const ReferenceResult r = trace_reference(s, design.face, ro);
  // Photon noise: compare on cells of about 128^2 pixels in all (box filter).
  int factor = 1;
  while (design.n / (2 * factor) >= 128 && design.n % (2 * factor) == 0) factor *= 2;
  const HdrImage shaped = tinted(design.face) ? brightest_channel(r.rgb) : r.image;
  Verification v = compare_with_target(design, shaped, target_exposure(target_irradiance(design)), factor);
  v.seconds = since(start);
  return v;
}

}  // namespace caustic::design
