// SPDX-License-Identifier: LGPL-2.1-or-later
// Work split into bands of rows on the machine's cores. The CPU halves of
// the pipeline (coverage.hpp's deposit, cpu_post.hpp's post-processing) run
// where a software renderer would otherwise run the same work on the same
// cores: each band touches only its own rows, so the bands share nothing
// but read-only inputs, need no locks, and compute every value as one
// thread would, to the bit.
//
// The helpers that take the other bands stay between calls, one crew per
// calling thread (a render thread's crew ends with it): starting and
// joining a thread costs 0.15-0.2 ms on the VM measured, a hand-over to a
// waiting helper a tenth of that, and a frame splits its work five times.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace caustic {

/// Helper threads that run bands 1.. of a job while the caller runs band 0.
class BandCrew {
 public:
  explicit BandCrew(int helpers);
  ~BandCrew();
  BandCrew(const BandCrew&) = delete;
  BandCrew& operator=(const BandCrew&) = delete;

  int helpers() const { return static_cast<int>(threads_.size()); }
  /// job(b) for every b in [0, bands): band 0, and those beyond the helpers,
  /// on the calling thread; returns when all ended. `job` must not throw.
  void run(int bands, const std::function<void(int)>& job);

 private:
  void serve(int band);

  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(int)>* job_ = nullptr;
  int bands_ = 0, pending_ = 0;
  unsigned generation_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

/// The machine's cores the bands use, at most 8.
int band_cores();

/// The calling thread's crew (band_cores() - 1 helpers), made on first use:
/// one a thread, whatever the work it splits.
BandCrew& band_crew();

/// Calls fn(lo, hi) for consecutive bands [lo, hi) covering [0, rows), one
/// band a core, each at least `min_rows` rows: a band thinner than that
/// costs more to hand over than it saves. The calling thread takes the first.
template <typename Fn>
void in_bands(int rows, int min_rows, Fn&& fn) {
  const int bands = std::clamp(rows / std::max(min_rows, 1), 1, band_cores());
  if (bands == 1) {
    fn(0, rows);
    return;
  }
  band_crew().run(bands, [&fn, rows, bands](int b) { fn(rows * b / bands, rows * (b + 1) / bands); });
}

}  // namespace caustic
