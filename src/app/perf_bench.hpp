// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench --perf`: frame costs as the mesh and the picture grow.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

namespace caustic::app {

/// The median of timed frames as both benches report it: the middle sample
/// (the upper one of the two middle samples for an even count).
inline double middle_sample(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct PerfOptions {
  std::filesystem::path out;
  int frames = 5;
  std::vector<int> meshes{64, 128, 256, 512, 1024};
  std::vector<int> sizes{256, 512, 1024, 2048};
};

/// Prints one line per (mesh, size) and writes perf.csv and perf.png/.svg
/// into `out`. Throws on GL failures.
int run_perf_bench(const PerfOptions& options);
/// `--spectral`: grey against spectral frames at 3, 8 and 16 wavelengths
/// for each mesh and size; prints the ratios and writes spectral.csv.
int run_spectral_bench(const PerfOptions& options);

}  // namespace caustic::app
