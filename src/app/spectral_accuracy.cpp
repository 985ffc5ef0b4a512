// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --spectral`, second part: how many wavelengths a
// dispersive frame needs. The prism scene (a 35 degree BK7 bar fanning
// daylight into a spectrum) at K = 1 ... 32 bands against the reference
// tracer at 32 bands, the densest sampling the scene format allows: the
// error is what band quantisation costs (a beam fans into K steps rather
// than a continuous spectrum), on the accuracy/speed chart as K grows.
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <sstream>

namespace caustic::app {
namespace {

// assets/scenes/prism.json, built in code: the bench needs no asset folder.
Scene prism_scene(int size, int wavelengths) {
  Scene s;
  s.mesh = "generated";
  s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
  s.object.ior = s.object.glass->index(optics::kLineD);
  s.object.flat_face_offset = 1.5;
  s.light.direction = {0, 0, -1};
  s.screen.center = {-86.33, 0, -180.41};
  s.screen.normal = glm::normalize(glm::dvec3(0.43165, 0, 0.90204));  // as the loader normalises it
  s.screen.up = {0, 1, 0};
  s.screen.width = s.screen.height = 24;
  s.render.width = s.render.height = size;
  s.render.wavelengths = wavelengths;
  return s;
}

// Mean over R, G, B of the relative L1 at 128 x 128 (box filter), where the
// reference's photon noise is small.
double rgb_l1_at_128(const RgbHdrImage& image, const RgbHdrImage& reference) {
  const int f = image.width / 128;
  double sum = 0;
  for (int c = 0; c < 3; ++c)
    sum += compare(box_down(channel(image, c), f), box_down(channel(reference, c), f)).relative_l1;
  return sum / 3;
}

}  // namespace

void run_spectral_accuracy(const std::filesystem::path& out, int frames, std::uint64_t photons, Engine& engine) {
  const int size = 1024;
  const auto mesh = std::make_shared<const Mesh>(grid_mesh(wedge(35.0 * std::numbers::pi / 180.0, 1.0, 8.0), 257, 257));
  ReferenceOptions ro;
  ro.photons = photons;
  const ReferenceResult ref = trace_reference(prism_scene(size, optics::kMaxWavelengths), *mesh, ro);
  std::printf("prism %d^2: reference at %d wavelengths, %.1f s\n", size, optics::kMaxWavelengths, ref.seconds);
  std::ostringstream csv;  // written whole at the end
  csv << "wavelengths,ray_ms,relative_l1_rgb\n";
  for (int k : {1, kPreviewWavelengths, 8, 16, optics::kMaxWavelengths}) {
    const Scene s = prism_scene(size, k);
    std::vector<double> ray;
    for (int f = 0; f < frames + 1; ++f) {
      engine.set_scene(s, std::make_shared<const Mesh>(*mesh));  // a new handle: a full frame
      engine.render();
      if (f > 0) ray.push_back(engine.stats().ray_ms);
    }
    const double l1 = rgb_l1_at_128(engine.read_hdr_rgb(), ref.rgb);
    csv << k << ',' << middle_sample(ray) << ',' << l1 << '\n';
    std::printf("prism %d^2, %2d wavelength%s: caustic %7.1f ms  relative L1 (mean of R, G, B) %.4f\n", size, k,
                k == 1 ? " " : "s", middle_sample(ray), l1);
    std::fflush(stdout);
  }
  write_text_files({{out / "spectral_accuracy.csv", csv.str()}});
  std::ostringstream plot;
  plot << "set datafile separator ','\nset grid\nset logscale xy\nset key off\n"
          "set xlabel 'caustic pass (ms), prism at 1024^2'\nset ylabel 'relative L1 (mean of R, G, B) against 32 bands'\n"
          "do for [f in 'png svg'] {\n"
          "  if (f eq 'png') { set terminal pngcairo size 800,500 } else { set terminal svg size 800,500 }\n"
          "  set output 'spectral_accuracy.'.f\n"
          "  plot 'spectral_accuracy.csv' using 2:3 every ::1 with linespoints pointsize 1.2, "
          "'' using 2:3:(sprintf('K = %d', $1)) every ::1 with labels offset 1.5,0.8\n}\n";
  write_text_files({{out / "spectral_accuracy.gp", plot.str()}});
  if (!run_gnuplot(out, "spectral_accuracy.gp", "gnuplot.log"))
    std::cerr << "causticd bench: gnuplot failed (see gnuplot.log); spectral_accuracy.csv is complete\n";
}

}  // namespace caustic::app
