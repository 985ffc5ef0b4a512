// SPDX-License-Identifier: LGPL-2.1-or-later
// Work split into bands of rows on the machine's cores. The CPU halves of
// the pipeline (coverage.hpp's deposit, cpu_post.hpp's post-processing) run
// where a software renderer would otherwise run the same work on the same
// cores: each band touches only its own rows, so the bands share nothing
// but read-only inputs and need no locks.
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace caustic {

/// Calls fn(lo, hi) for consecutive bands [lo, hi) covering [0, rows), one
/// band a core (at most 8), each at least `min_rows` rows: a thread costs
/// more than a thin band saves. The calling thread takes the first band.
template <typename Fn>
void in_bands(int rows, int min_rows, Fn&& fn) {
  const int cores = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
  const int bands = std::clamp(rows / std::max(min_rows, 1), 1, cores);
  std::vector<std::thread> helpers;
  for (int b = 1; b < bands; ++b)
    helpers.emplace_back([&fn, rows, b, bands] { fn(rows * b / bands, rows * (b + 1) / bands); });
  fn(0, rows / bands);
  for (auto& h : helpers) h.join();
}

}  // namespace caustic
