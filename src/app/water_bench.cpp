// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --water`: what a frame of living water costs. Each frame
// advances the pool by a thirtieth of a second (whole solver steps, rain
// falling), turns the heights into the surface mesh, renders the caustic on
// the floor and post-processes it, and reads the picture back as I420, as
// the stream does; the frame is new every time, so nothing is cached.
// Then the simulation alone, on the CPU and on the GL.
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_io.hpp"
#include "caustic/water_mesh.hpp"
#include "caustic/wave_gl.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace caustic::app {
namespace {

constexpr double kFrame = 1.0 / 30;

// The gallery's pool (assets/scenes/pool.json): 2 m of water in a breeze
// and light rain, its floor 1.2 m down under a sun 20 degrees off vertical,
// the picture the floor where the light lands.
Scene pool_scene(int size) {
  Scene s;
  s.mesh = "generated";
  s.object.shape = Shape::surface;
  s.object.ior = 1.333;
  s.light.direction = glm::normalize(glm::dvec3(0.342, 0, -0.94));
  s.screen.center = {0.32, 0, -1.2};
  s.screen.width = s.screen.height = 2.0;
  s.screen.follow_light = false;
  s.render.width = s.render.height = size;
  s.render.fresnel = true;
  s.post.gamma = 1.0;
  s.post.auto_percentile = 0.995;
  s.post.bloom_strength = 0.2;
  s.post.bloom_radius = 4;
  return s;
}

water::WaveParams pool_water(int grid) {
  water::WaveParams p;
  p.grid = grid;
  p.rain_rate = 8;
  p.rain_strength = 0.006;
  p.drop_radius = 0.04;
  p.wind_height = 0.001;
  p.wind_direction_deg = 60;
  p.wind_wavelength = 0.3;
  p.seed = 7;
  // Coarse grids: drops one spacing wide, wind waves eight spacings long.
  p.drop_radius = std::max(p.drop_radius, water::spacing(p));
  p.wind_wavelength = std::max(p.wind_wavelength, 8 * water::spacing(p));
  // Whole steps per frame, each within the stability bound.
  p.time_step = kFrame / std::ceil(kFrame / water::max_time_step(p));
  return p;
}

// The simulation alone, a frame's steps at a time, on the CPU and on the GL
// (finished, then read back as the CPU's surface mesh would need it).
void time_solvers(const std::vector<int>& grids, double seconds, const std::filesystem::path& out) {
  std::ostringstream csv;  // written whole at the end
  csv << "grid,steps_per_frame,cpu_ms,gl_ms,gl_readback_ms\n";
  for (int grid : grids) {
    const water::WaveParams params = pool_water(grid);
    const int steps = static_cast<int>(std::lround(kFrame / params.time_step));
    water::WaveSolver cpu(params);
    water::WaveSolverGl gl(params);
    std::vector<double> cpu_ms, gl_ms, read_ms;
    for (int frame = 0; frame < std::max(1, static_cast<int>(seconds / kFrame)); ++frame) {
      auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < steps; ++i) cpu.step();
      cpu_ms.push_back(ms_since(t0));
      t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < steps; ++i) gl.step();
      gl.finish();
      gl_ms.push_back(ms_since(t0));
      t0 = std::chrono::steady_clock::now();
      const auto heights = gl.heights();
      read_ms.push_back(ms_since(t0));
    }
    std::printf("solver grid %3d^2, %d steps/frame: CPU %6.2f ms, GL %6.2f ms (+ read-back %5.2f ms), medians\n", grid,
                steps, middle_sample(cpu_ms), middle_sample(gl_ms), middle_sample(read_ms));
    csv << grid << ',' << steps << ',' << middle_sample(cpu_ms) << ',' << middle_sample(gl_ms) << ','
        << middle_sample(read_ms) << '\n';
  }
  write_text_files({{out / "water-solver.csv", csv.str()}});
}

// --setups' spelling of a setup.
std::string setup_name(TriangleSetup setup) {
  for (const auto& [name, value] : kTriangleSetups)
    if (value == setup) return name;
  return "?";
}

// Each setup at each divisor, a row each.
std::vector<std::pair<TriangleSetup, int>> rows(const WaterBenchOptions& water) {
  std::vector<std::pair<TriangleSetup, int>> out;
  for (TriangleSetup setup : water.setups)
    for (int divisor : water.divisors) out.emplace_back(setup, divisor);
  return out;
}

}  // namespace

int run_water_bench(const PerfOptions& opt, const WaterBenchOptions& water) {
  const double seconds = water.seconds;
  GlContext context(egl_platform_from_environment());
  std::ostringstream csv;  // written whole at the end
  csv << "grid,pixels,setup,divisor,steps_per_frame,sim_ms,mesh_ms,caustic_ms,post_ms,i420_ms,frame_ms,frame_p95_ms,"
         "over_budget,frames\n";
  std::printf("renderer: %s; %.0f s of water per row, one frame per 1/30 s\n", context.renderer().c_str(), seconds);
  for (int grid : water.grids) {
    for (int size : opt.sizes) {
      for (const auto& [setup, divisor] : rows(water)) {
        const water::WaveParams params = pool_water(grid);
        const int steps = static_cast<int>(std::lround(kFrame / params.time_step));
        water::WaveSolver solver(params);
        const Scene scene = pool_scene(size);
        Engine engine;
        engine.set_triangle_setup(setup);
        engine.set_preview_divisor(divisor);
        std::vector<std::uint8_t> picture;
        std::vector<double> sim, mesh_ms, caustic, post, i420, frame;
        const int frames = static_cast<int>(std::lround(seconds / kFrame));
        for (int f = 0; f < frames + 1; ++f) {
          auto t0 = std::chrono::steady_clock::now();
          for (int i = 0; i < steps; ++i) solver.step();
          const double sim_ms = ms_since(t0);
          t0 = std::chrono::steady_clock::now();
          auto mesh = std::make_shared<const Mesh>(water::water_mesh(solver, divisor));  // thinned as streamed
          const double built_ms = ms_since(t0);
          t0 = std::chrono::steady_clock::now();
          engine.set_scene(scene, std::move(mesh));
          engine.render();
          const double rendered_ms = ms_since(t0);
          t0 = std::chrono::steady_clock::now();
          picture.resize(engine.picture_bytes(PixelFormat::i420));
          std::uint64_t tag = 0;
          engine.start_readback(static_cast<std::uint64_t>(f), PixelFormat::i420);
          engine.poll_readback(picture.data(), picture.size(), &tag, true);
          const double read_ms = ms_since(t0);
          if (f == 0) continue;  // warm-up: shaders compile
          sim.push_back(sim_ms);
          mesh_ms.push_back(built_ms);
          caustic.push_back(engine.stats().ray_ms);
          post.push_back(engine.stats().post_ms);
          i420.push_back(read_ms);
          frame.push_back(sim_ms + built_ms + rendered_ms + read_ms);
        }
        // The last frame, to look at.
        const std::string suffix = (water.setups.size() > 1 ? "-" + setup_name(setup) : "") +
                                   (water.divisors.size() > 1 ? "-p" + std::to_string(divisor) : "");
        write_png(engine.read_ldr(),
                  opt.out / ("water-" + std::to_string(grid) + "-" + std::to_string(size) + suffix + ".png"));
        int over = 0;
        for (double ms : frame) over += ms > 1000 * kFrame;
        std::vector<double> sorted = frame;
        std::sort(sorted.begin(), sorted.end());
        const double p95 = sorted[static_cast<std::size_t>(0.95 * static_cast<double>(sorted.size() - 1))];
        const std::string where = engine.stats().cpu_setup ? "cpu" : "gpu";
        const std::string level = divisor == 1 ? "full" : "preview 1/" + std::to_string(divisor);
        csv << grid << ',' << size << ',' << where << ',' << divisor << ',' << steps << ','
            << middle_sample(sim) << ',' << middle_sample(mesh_ms) << ','
            << middle_sample(caustic) << ',' << middle_sample(post) << ',' << middle_sample(i420) << ','
            << middle_sample(frame) << ',' << p95 << ',' << over << ',' << frame.size() << '\n';
        std::printf("grid %3d^2, %4d^2 px, setup %s, %s, %d steps/frame: sim %5.2f ms  mesh %5.2f ms  "
                    "caustic %6.1f ms  post %5.1f ms  "
                    "I420 %5.1f ms  frame %6.1f ms (p95 %6.1f)  %d of %zu frames over 33.3 ms; %llu raindrops\n",
                    grid, size, where.c_str(), level.c_str(), steps, middle_sample(sim), middle_sample(mesh_ms),
                    middle_sample(caustic),
                    middle_sample(post), middle_sample(i420), middle_sample(frame), p95, over, frame.size(),
                    static_cast<unsigned long long>(solver.raindrops()));
        std::fflush(stdout);
      }
    }
  }
  write_text_files({{opt.out / "water.csv", csv.str()}});
  time_solvers(water.grids, seconds, opt.out);
  std::printf("wrote %s/water.csv, water-solver.csv and the last frame of each row, "
              "water-GRID-SIZE[-SETUP][-pDIVISOR].png\n",
              opt.out.string().c_str());
  return 0;
}

}  // namespace caustic::app
