// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --perf`: frame costs as the mesh and the picture grow.
#pragma once

#include "caustic/engine.hpp"
#include "caustic/mesh.hpp"
#include "caustic/surfaces.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic::app {

/// The median of timed frames as both benches report it: the middle sample
/// (the upper one of the two middle samples for an even count).
inline double middle_sample(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Milliseconds since `t0`, as the benches time each stage of a frame.
inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The frame both benches time: the 20 mm plano-convex lens (R = 40 mm) on
/// an n x n grid, seen on a 30 mm screen 60 mm below, `size` pixels a side.
inline std::shared_ptr<const Mesh> bench_lens_mesh(int n) {
  return std::make_shared<const Mesh>(grid_mesh(plano_convex_lens(40.0, 10.0), n, n));
}
inline Scene bench_lens_scene(int size) {
  Scene s;
  s.mesh = "generated";
  s.object.flat_face_offset = 4.0;
  s.screen.center = {0, 0, -60};
  s.screen.width = s.screen.height = 30;
  s.render.width = s.render.height = size;
  return s;
}

struct PerfOptions {
  std::filesystem::path out;
  int frames = 5;
  std::vector<int> meshes{64, 128, 256, 512, 1024};
  std::vector<int> sizes{256, 512, 1024, 2048};
  std::uint64_t photons = 16'000'000;  ///< --spectral: photons of the prism's reference
};

/// Makes the --out folder and tries a file in it; when either fails says so
/// ("causticd bench: --out DIR: ...") and returns false, before any work.
bool bench_folder_ready(const std::filesystem::path& out);

/// Runs `gnuplot script` inside `folder` (no shell: any folder name is
/// safe), its messages into the file `log` there. True when it succeeded.
bool run_gnuplot(const std::filesystem::path& folder, const char* script, const char* log);

/// Prints one line per (mesh, size) and writes perf.csv and perf.png/.svg
/// into `out`. Throws on GL failures.
int run_perf_bench(const PerfOptions& options);
/// `--spectral`: grey against spectral frames at 3, 8 and 16 wavelengths
/// for each mesh and size; prints the ratios and writes spectral.csv. Then
/// the prism's error against the number of wavelengths:
/// spectral_accuracy.csv and .png/.svg.
int run_spectral_bench(const PerfOptions& options);

/// `--multipass`: a biconvex solid (faces --meshes a side) at light grids
/// of 64 to 512 rays a side per --sizes: time and error against --photons
/// of reference; prints the rows and writes multipass.csv.
int run_multipass_bench(const PerfOptions& options);

/// What `--water` times besides the sizes: water grids (vertices per side),
/// seconds of water a row, where the triangles are set up, and the caustic's
/// divisors (1: full frames; 2: previews, the caustic at half size and no
/// bloom, as the stream draws them).
struct WaterBenchOptions {
  std::vector<int> grids{128, 256};
  double seconds = 3.0;
  std::vector<TriangleSetup> setups{TriangleSetup::automatic};
  std::vector<int> divisors{1};
};

/// `--water`: a rainy pool's frames (simulation, surface mesh, caustic on
/// the floor, post, I420 read-back) for each water grid and --sizes over
/// `water.seconds` of water; prints medians, the 95th percentile and the
/// frames over the 33.3 ms budget, and writes water.csv and each row's last
/// frame (water-GRID-SIZE[-SETUP][-pDIVISOR].png), a row for each setup and divisor.
int run_water_bench(const PerfOptions& options, const WaterBenchOptions& water);

/// The names of the triangle setups, as --setups spells them.
inline const std::map<std::string, TriangleSetup> kTriangleSetups{
    {"auto", TriangleSetup::automatic}, {"gpu", TriangleSetup::gpu}, {"cpu", TriangleSetup::cpu}};

/// The second part of --spectral (spectral_accuracy.cpp).
void run_spectral_accuracy(const std::filesystem::path& out, int frames, std::uint64_t photons, Engine& engine);

}  // namespace caustic::app
