// SPDX-License-Identifier: LGPL-2.1-or-later
// Counters and histograms for GET /metrics (Prometheus text format 0.0.4).
// Updated from streaming threads and the main loop alike.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace caustic::server {

/// Cumulative histogram with fixed bucket bounds in milliseconds.
class Histogram {
 public:
  static constexpr std::array<double, 10> kBoundsMs = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
  void observe(double ms);
  std::string render(const std::string& name, const std::string& help) const;

 private:
  mutable std::mutex mutex_;
  std::array<std::uint64_t, kBoundsMs.size()> buckets_{};
  std::uint64_t count_ = 0;
  double sum_ = 0;
};

struct Metrics {
  std::atomic<std::uint64_t> sessions_created{0};
  std::atomic<std::uint64_t> sessions_rejected{0};
  std::atomic<std::uint64_t> frames_rendered{0};  ///< caustic passes
  std::atomic<std::uint64_t> render_overruns{0};  ///< frames re-sent because a render outlasted its interval
  std::atomic<std::uint64_t> frames_dropped{0};   ///< frames the encoder queue dropped, the encoder still busy
  std::atomic<std::uint64_t> frames_sent{0};      ///< encoded frames handed to the payloader
  std::atomic<std::uint64_t> parameter_updates{0};
  std::atomic<std::uint64_t> water_drops{0};
  std::atomic<std::uint64_t> http_errors{0};      ///< 4xx and 5xx answers
  std::atomic<std::uint64_t> pipeline_errors{0};
  std::atomic<std::uint64_t> connections_accepted{0};
  std::atomic<std::uint64_t> connections_refused{0};    ///< answered by the accept path itself (limits, bad heads)
  std::atomic<std::uint64_t> connections_timed_out{0};  ///< closed for a late head or answer
  std::atomic<std::uint64_t> accept_failures{0};        ///< accepts that failed for want of descriptors
  std::atomic<std::uint64_t> rate_limited{0};           ///< 429 answers
  std::atomic<std::uint64_t> sessions_reclaimed{0};     ///< ended for an idle or silent viewer
  std::atomic<std::uint64_t> designs_submitted{0};      ///< pictures queued for design
  std::atomic<std::uint64_t> designs_refused{0};        ///< uploads answered 4xx or 503
  Histogram render_ms;
  Histogram encode_ms;

  /// Everything in Prometheus text format; `sessions` and `connections` are the live counts.
  std::string render(std::size_t sessions, std::size_t connections) const;
};

}  // namespace caustic::server
