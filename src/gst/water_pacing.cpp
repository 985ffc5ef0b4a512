// SPDX-License-Identifier: LGPL-2.1-or-later
#include "water_pacing.hpp"

#include <algorithm>

namespace caustic::gst {
namespace {

// Previews are averaged over about four frames: one slow preview (a page
// fault, a scheduler hiccup) should not stop a try, nor one fast one cause it.
constexpr double kPreviewWeight = 0.25;

}  // namespace

void WaterPacing::learn_ratio(double ratio) {
  ratios_[static_cast<std::size_t>(ratios_seen_ % static_cast<int>(ratios_.size()))] = ratio;
  ++ratios_seen_;
}

double WaterPacing::ratio() const {
  const auto count = static_cast<std::size_t>(std::min(ratios_seen_, static_cast<int>(ratios_.size())));
  if (count == 0) return 0;
  auto recent = ratios_;
  const auto lower = recent.begin() + static_cast<std::ptrdiff_t>((count - 1) / 2);
  std::nth_element(recent.begin(), lower, recent.begin() + static_cast<std::ptrdiff_t>(count));
  return *lower;
}

void WaterPacing::full_drawn(double ms, Clock::time_point now) {
  full_ms_ = ms;
  full_at_ = now;
  // A fit ends a spell of misses: the next overload's first retry comes
  // soon again, not after `blind`.
  misses_ = ms > budget_ms_ ? misses_ + 1 : 0;
  // Previews drawn before an earlier full frame say nothing of this one's load.
  ratio_from_next_ = !preview_fresh_;
  if (preview_fresh_) learn_ratio(ms / preview_ms_);
  preview_fresh_ = false;
}

void WaterPacing::preview_drawn(double ms) {
  if (ms <= 0) return;
  if (!preview_fresh_) preview_ms_ = ms;  // a new run of previews
  preview_ms_ += kPreviewWeight * (ms - preview_ms_);
  if (ratio_from_next_ && full_ms_ > 0) {
    learn_ratio(full_ms_ / ms);
    ratio_from_next_ = false;
  }
  preview_fresh_ = true;
}

double WaterPacing::predicted_full_ms() const {
  const double scale = ratio();
  return scale > 0 && preview_fresh_ ? scale * preview_ms_ : full_ms_;
}

bool WaterPacing::want_full(Clock::time_point now) const {
  if (full_ms_ <= 0 || full_ms_ <= budget_ms_) return true;
  return predicted_full_ms() <= budget_ms_ || now - full_at_ >= (misses_ <= 1 ? first_ : blind_);
}

}  // namespace caustic::gst
