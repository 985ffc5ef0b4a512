// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --spectral`: what colour costs. The same lens frame grey
// (one caustic pass) and spectral in BK7 at K wavelengths (K passes into a
// colour target, colour post-processing), at each --meshes x --sizes pair;
// the ratio to grey is the figure docs/performance.md quotes.
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/surfaces.hpp"

#include <cstdio>
#include <ctime>
#include <memory>
#include <sstream>
#include <vector>

namespace caustic::app {
namespace {

// The process's CPU time (every thread's, llvmpipe's included), ms: on a
// shared machine whose speed swings it moves less than wall time does, and
// over two cores it tells whether a frame used both.
double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

}  // namespace

int run_spectral_bench(const PerfOptions& opt) {
  GlContext context(egl_platform_from_environment());
  std::ostringstream csv;  // written whole at the end
  csv << "mesh,pixels,wavelengths,ray_ms,post_ms,frame_ms,ratio_to_grey,cpu_ms,cpu_ratio_to_grey\n";
  std::printf("renderer: %s; median of %d frames per row\n", context.renderer().c_str(), opt.frames);
  const std::vector<int> counts{1, kPreviewWavelengths, 8, 16};  // 1: the grey frame, no glass
  for (int n : opt.meshes) {
    const auto mesh = bench_lens_mesh(n);
    for (int size : opt.sizes) {
      // An engine each, their frames taken in turn: this machine's speed
      // swings by a quarter within minutes, and rows timed one after the
      // other compared different minutes, not different frames.
      std::vector<std::unique_ptr<Engine>> engines;
      std::vector<Scene> scenes;
      for (int k : counts) {
        Scene s = bench_lens_scene(size);
        if (k > 1) {
          s.object.glass = Glass{"bk7", optics::find_material("bk7")->law};
          s.object.ior = s.object.glass->index(optics::kLineD);
          s.render.wavelengths = k;
        }
        scenes.push_back(s);
        engines.push_back(std::make_unique<Engine>());
      }
      std::vector<std::vector<double>> ray(counts.size()), post(counts.size()), frame(counts.size()),
          cpu(counts.size());
      for (int f = 0; f < opt.frames + 1; ++f)
        for (std::size_t c = 0; c < counts.size(); ++c) {
          Engine& e = *engines[c];
          e.set_scene(scenes[c], std::make_shared<const Mesh>(*mesh));  // a new handle: a full frame
          const double cpu_before = process_cpu_ms();
          e.render();
          if (f == 0) continue;  // warm-up
          cpu[c].push_back(process_cpu_ms() - cpu_before);
          ray[c].push_back(e.stats().ray_ms);
          post[c].push_back(e.stats().post_ms);
          frame[c].push_back(e.stats().ray_ms + e.stats().post_ms);
        }
      const double grey_ms = middle_sample(frame[0]), grey_cpu = middle_sample(cpu[0]);
      for (std::size_t c = 0; c < counts.size(); ++c) {
        const int k = counts[c];
        const double ms = middle_sample(frame[c]), cpu_ms = middle_sample(cpu[c]);
        csv << n << ',' << size << ',' << k << ',' << middle_sample(ray[c]) << ',' << middle_sample(post[c]) << ','
            << ms << ',' << ms / grey_ms << ',' << cpu_ms << ',' << cpu_ms / grey_cpu << '\n';
        std::printf("mesh %4d^2, %4d^2 px, %2d wavelength%s: caustic %7.1f ms  post %6.1f ms  frame %7.1f ms  "
                    "%.2fx grey  (CPU %7.1f ms, %.2fx grey)\n",
                    n, size, k, k == 1 ? " " : "s", middle_sample(ray[c]), middle_sample(post[c]), ms, ms / grey_ms,
                    cpu_ms, cpu_ms / grey_cpu);
      }
      std::fflush(stdout);
    }
  }
  write_text_files({{opt.out / "spectral.csv", csv.str()}});
  Engine engine;
  run_spectral_accuracy(opt.out, opt.frames, opt.photons, engine);
  std::printf("wrote %s/spectral.csv, spectral_accuracy.csv, spectral_accuracy.png/.svg\n", opt.out.string().c_str());
  return 0;
}

}  // namespace caustic::app
