// SPDX-License-Identifier: LGPL-2.1-or-later
// When moving water gets a full frame. Water is never still, so its frames
// are full ones while a full frame fits the render budget and previews
// while it does not. Whether one would fit again is judged from the
// previews: what slows a render (the encoder on the same cores, other
// sessions) slows a preview and a full frame alike, so the last full
// frame's cost, scaled by how much cheaper previews have become since,
// predicts the next one. The scaling is the lower median of the last few
// full-to-preview ratios, so that one slow frame (a hiccup of the machine,
// the renderer's warm-up) next to a normal one does not hold full frames
// back until the next blind try. A try that does not fit is an overrun (the stream
// sends a picture again), so tries go by the prediction, and only rare
// blind ones check it: one soon after the first miss (whose cost may hold
// the renderer's warm-up), then one every `blind`.
#pragma once

#include <array>
#include <chrono>

namespace caustic::gst {

class WaterPacing {
 public:
  using Clock = std::chrono::steady_clock;

  /// `budget_ms`: the render time a full frame may take. While none is
  /// predicted to fit, the first miss is tried again after `first`, later
  /// ones after `blind`.
  explicit WaterPacing(double budget_ms = 1e300, std::chrono::milliseconds first = std::chrono::seconds(1),
                       std::chrono::milliseconds blind = std::chrono::seconds(60))
      : budget_ms_(budget_ms), first_(first), blind_(blind) {}

  /// A full frame's render took `ms`.
  void full_drawn(double ms, Clock::time_point now);
  /// A preview's render took `ms`.
  void preview_drawn(double ms);
  /// Whether the next frame should be a full one: always the first, then
  /// while the last fitted, when the previews predict one would, or when a
  /// blind try is due.
  bool want_full(Clock::time_point now) const;
  double budget_ms() const { return budget_ms_; }
  /// The last full frame's cost scaled by the previews' (0: no full frame yet).
  double predicted_full_ms() const;

 private:
  double budget_ms_;
  std::chrono::milliseconds first_, blind_;
  void learn_ratio(double ratio);
  double ratio() const;  // 0: none learnt yet

  double full_ms_ = 0, preview_ms_ = 0;
  std::array<double, 5> ratios_{};  // full / preview cost around the last full frames, a ring
  int ratios_seen_ = 0;
  bool ratio_from_next_ = false;  // no preview just before that full frame: learn it from the next
  bool preview_fresh_ = false;    // the last frame drawn was a preview
  int misses_ = 0;                // full frames that did not fit
  Clock::time_point full_at_{};
};

}  // namespace caustic::gst
