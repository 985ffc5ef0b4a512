// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --perf`: what a frame costs as the mesh and the picture
// grow: caustic pass, post-processing, and the two ways out of GL (RGBA
// read-back, and I420 converted on the GPU then read back). Writes perf.csv
// and a chart (time against triangles and against pixels).
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/surfaces.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace caustic::app {
namespace {

void write_perf_chart(const std::filesystem::path& out, const std::vector<int>& sizes, const std::vector<int>& meshes) {
  const int mesh = meshes[meshes.size() / 2];  // the per-pixel stages, at a middle mesh
  std::ostringstream plot;
  plot << "set datafile separator ','\nset grid\nset logscale xy\nset key inside top left\n"
          "set format x '10^{%T}'\nfiles = 'png svg'\ndo for [f in files] {\n"
          "  if (f eq 'png') { set terminal pngcairo size 1100,500 } else { set terminal svg size 1100,500 }\n"
          "  set output 'perf.'.f\n  set multiplot layout 1,2\n"
          "  set xlabel 'triangles'\n  set ylabel 'caustic pass (ms)'\n  plot ";
  for (std::size_t i = 0; i < sizes.size(); ++i)
    plot << (i ? ", " : "") << "'perf.csv' using ($2 == " << sizes[i] << " ? $3 : 1/0):4 with points pointsize 1.3 title '"
         << sizes[i] << "^2 px'";
  plot << "\n  set xlabel 'pixels'\n  set ylabel 'ms per frame (mesh " << mesh << "^2)'\n"
       << "  plot 'perf.csv' using ($1 == " << mesh << " ? $2*$2 : 1/0):5 with linespoints title 'post', "
       << "'' using ($1 == " << mesh << " ? $2*$2 : 1/0):6 with linespoints title 'RGBA read-back', "
       << "'' using ($1 == " << mesh << " ? $2*$2 : 1/0):7 with linespoints title 'I420 convert + read-back'\n"
       << "  unset multiplot\n}\n";
  write_text_files({{out / "perf.gp", plot.str()}});
  if (!run_gnuplot(out, "perf.gp", "gnuplot-perf.log")) std::cerr << "causticd bench: gnuplot failed; perf.csv is complete\n";
}

}  // namespace

int run_perf_bench(const PerfOptions& opt) {
  GlContext context(egl_platform_from_environment());
  Engine engine;
  std::ostringstream csv;  // written whole at the end
  csv << "mesh,pixels,triangles,ray_ms,post_ms,rgba_readback_ms,i420_ms\n";
  std::printf("renderer: %s; median of %d frames per row\n", context.renderer().c_str(), opt.frames);
  for (int n : opt.meshes) {
    const auto mesh = bench_lens_mesh(n);
    for (int size : opt.sizes) {
      const Scene s = bench_lens_scene(size);
      std::vector<double> ray, post, rgba, i420;
      std::vector<std::uint8_t> buffer;
      std::uint64_t tag = 0;
      for (int f = 0; f < opt.frames + 1; ++f) {
        engine.set_scene(s, std::make_shared<const Mesh>(*mesh));  // a new handle: a full frame
        engine.render();
        auto t0 = std::chrono::steady_clock::now();
        engine.start_readback(1, PixelFormat::rgba);
        buffer.resize(engine.picture_bytes(PixelFormat::rgba));
        engine.poll_readback(buffer.data(), buffer.size(), &tag, true);
        const double rgba_ms = ms_since(t0);
        t0 = std::chrono::steady_clock::now();
        engine.start_readback(2, PixelFormat::i420);
        buffer.resize(engine.picture_bytes(PixelFormat::i420));
        engine.poll_readback(buffer.data(), buffer.size(), &tag, true);
        const double i420_ms = ms_since(t0);
        if (f == 0) continue;  // warm-up
        ray.push_back(engine.stats().ray_ms);
        post.push_back(engine.stats().post_ms);
        rgba.push_back(rgba_ms);
        i420.push_back(i420_ms);
      }
      const std::size_t triangles = mesh->triangles.size();
      csv << n << ',' << size << ',' << triangles << ',' << middle_sample(ray) << ',' << middle_sample(post) << ','
          << middle_sample(rgba) << ',' << middle_sample(i420) << '\n';
      std::printf("mesh %4d^2 (%8zu triangles), %4d^2 px: caustic %7.1f ms  post %6.1f ms  RGBA read-back %6.1f ms  "
                  "I420 %6.1f ms\n",
                  n, triangles, size, middle_sample(ray), middle_sample(post), middle_sample(rgba), middle_sample(i420));
      std::fflush(stdout);
    }
  }
  write_text_files({{opt.out / "perf.csv", csv.str()}});
  write_perf_chart(opt.out, opt.sizes, opt.meshes);
  std::printf("wrote %s/perf.csv, perf.png, perf.svg\n", opt.out.string().c_str());
  return 0;
}

}  // namespace caustic::app
