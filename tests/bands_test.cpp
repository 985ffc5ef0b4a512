// SPDX-License-Identifier: LGPL-2.1-or-later
// in_bands (src/engine/bands.hpp): every row in exactly one band, whatever
// the rows, the minimum and the crew's size; calls from several threads at
// once (each with its own crew) and a crew outliving many jobs.
#include "bands.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace caustic {
namespace {

// The rows each call saw, counted: 1 everywhere, and the bands' number.
void expect_each_row_once(int rows, int min_rows) {
  std::vector<std::atomic<int>> seen(static_cast<std::size_t>(rows));
  std::atomic<int> bands{0};
  in_bands(rows, min_rows, [&](int lo, int hi) {
    ++bands;
    for (int r = lo; r < hi; ++r) ++seen[static_cast<std::size_t>(r)];
  });
  for (int r = 0; r < rows; ++r) ASSERT_EQ(seen[static_cast<std::size_t>(r)], 1) << "row " << r << " of " << rows;
  EXPECT_GE(bands, 1);
  EXPECT_LE(bands, band_cores());
  if (rows > 0) {
    EXPECT_LE(bands, std::max(1, rows / std::max(min_rows, 1)));
  }
}

TEST(Bands, EveryRowInExactlyOneBand) {
  for (const int rows : {0, 1, 7, 64, 65, 127, 128, 1000, 1024})
    for (const int min_rows : {0, 1, 16, 64, 2000}) expect_each_row_once(rows, min_rows);
}

TEST(Bands, ThreadsCallAtOnceEachWithItsOwnCrew) {
  std::vector<std::thread> callers;
  std::atomic<int> wrong{0};
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&wrong, t] {
      for (int job = 0; job < 200; ++job) {
        const int rows = 64 + 37 * t + job;
        std::vector<int> seen(static_cast<std::size_t>(rows), 0);  // bands write disjoint rows
        in_bands(rows, 8, [&](int lo, int hi) {
          for (int r = lo; r < hi; ++r) ++seen[static_cast<std::size_t>(r)];
        });
        for (int s : seen) wrong += s != 1;
      }
    });
  for (auto& c : callers) c.join();
  EXPECT_EQ(wrong, 0);
}

// The process's threads, from /proc.
int threads_now() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("Threads:", 0) == 0) return std::stoi(line.substr(8));
  return -1;
}

TEST(Bands, OneCrewAThreadWhateverTheWork) {
  if (band_cores() < 2) GTEST_SKIP() << "one core: in_bands needs no helpers";
  // Three call sites, three instantiations of in_bands, on a fresh thread:
  // one crew of helpers appears, not one a call site.
  int before = 0, after = 0;
  std::thread([&] {
    before = threads_now();
    in_bands(256, 1, [](int, int) {});
    in_bands(256, 1, [&before](int, int) { (void)before; });
    in_bands(256, 1, [&after](int, int) { (void)after; });
    after = threads_now();
  }).join();
  EXPECT_EQ(after - before, band_cores() - 1);
}

TEST(Bands, ACrewRunsEveryBandWhetherFewerOrMoreThanItsHelpers) {
  BandCrew crew(3);
  for (int bands = 1; bands <= 7; ++bands) {
    std::vector<int> ran(static_cast<std::size_t>(bands), 0);
    std::mutex m;
    crew.run(bands, [&](int b) {
      std::lock_guard lock(m);
      ++ran[static_cast<std::size_t>(b)];
    });
    EXPECT_EQ(ran, std::vector<int>(static_cast<std::size_t>(bands), 1)) << bands << " bands";
  }
}

}  // namespace
}  // namespace caustic
