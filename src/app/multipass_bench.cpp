// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --multipass`: what a solid costs. A biconvex lens with two
// n x n faces (--meshes) traced by the multipass method at light grids of
// 64..512 rays a side, at each --sizes: the caustic pass's time (CPU trace
// plus GPU splat) and its error against the photon reference, both images
// box-filtered to 128 x 128 as every accuracy figure here is.
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/exposure.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"
#include "caustic/surfaces.hpp"

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace caustic::app {

Scene bench_biconvex_scene(int size) {
  // The gallery's biconvex lens (R = 40 mm both faces, 6 mm thick, 20 mm
  // square), its screen 8 mm before the focus.
  Scene s;
  s.mesh = "generated";
  s.object.shape = Shape::solid;
  s.screen.center = {0, 0, -34};
  s.screen.width = s.screen.height = 12;
  s.render.width = s.render.height = size;
  s.render.fresnel = true;
  return s;
}

int run_multipass_bench(const PerfOptions& opt) {
  GlContext context(egl_platform_from_environment());
  Engine engine;
  std::ostringstream csv;  // written whole at the end
  csv << "faces,pixels,light_grid,ray_ms,trace_ms,relative_l1\n";
  std::printf("renderer: %s; median of %d frames per row; reference %llu photons\n", context.renderer().c_str(),
              opt.frames, static_cast<unsigned long long>(opt.photons));
  for (int n : opt.meshes) {
    const auto mesh = std::make_shared<const Mesh>(biconvex_lens(40.0, 40.0, 6.0, 10.0, n));
    for (int size : opt.sizes) {
      Scene s = bench_biconvex_scene(size);
      ReferenceOptions ro;
      ro.photons = opt.photons;
      const HdrImage reference = box_down(trace_reference(s, *mesh, ro).image, size / 128);
      for (int grid : {64, 128, 256, 512}) {
        s.render.light_grid = grid;
        std::vector<double> ray, trace;
        for (int f = 0; f < opt.frames + 1; ++f) {
          engine.set_scene(s, std::make_shared<const Mesh>(*mesh));  // a new handle: a full frame
          engine.render();
          if (f == 0) continue;  // warm-up
          ray.push_back(engine.stats().ray_ms);
          trace.push_back(engine.stats().trace_ms);
        }
        const double l1 = compare(box_down(engine.read_hdr(), size / 128), reference,
                                  exposure::settled_exposure(s.post, reference), s.post.gamma)
                              .relative_l1;
        csv << n << ',' << size << ',' << grid << ',' << middle_sample(ray) << ',' << middle_sample(trace) << ','
            << l1 << '\n';
        std::printf("faces %4d^2, %4d^2 px, light grid %3d^2: caustic %7.1f ms (CPU trace %6.1f ms)  L1 %.4f\n", n,
                    size, grid, middle_sample(ray), middle_sample(trace), l1);
        std::fflush(stdout);
      }
    }
  }
  write_text_files({{opt.out / "multipass.csv", csv.str()}});
  // One size (the default): it goes in the axis label and each point's
  // label names only its grid, short enough not to run into the next.
  const bool one_size = opt.sizes.size() == 1;
  const std::string axis = one_size ? "caustic pass at " + std::to_string(opt.sizes[0]) + "^2 px (ms): CPU trace + splat"
                                    : "caustic pass (ms): CPU trace + splat";
  const std::string label = one_size ? "sprintf('%d^2 rays', $3)" : "sprintf('%d^2 rays, %d^2 px', $3, $2)";
  std::ostringstream plot;
  plot << "set datafile separator ','\nset grid\nset logscale xy\nset key off\n"
          "set xlabel '" << axis << "'\nset ylabel 'relative L1 against the reference'\n"
          "do for [f in 'png svg'] {\n"
          "  if (f eq 'png') { set terminal pngcairo size 800,500 } else { set terminal svg size 800,500 }\n"
          "  set output 'multipass.'.f\n"
          "  plot 'multipass.csv' using 4:6 every ::1 with linespoints pointsize 1.2, "
          "'' using 4:6:(" << label << ") every ::1 with labels left offset 1,0.7\n}\n";
  write_text_files({{opt.out / "multipass.gp", plot.str()}});
  if (!run_gnuplot(opt.out, "multipass.gp", "gnuplot.log"))
    std::cerr << "causticd bench: gnuplot failed (see gnuplot.log); multipass.csv is complete\n";
  std::printf("wrote %s/multipass.csv, multipass.png/.svg\n", opt.out.string().c_str());
  return 0;
}

}  // namespace caustic::app
