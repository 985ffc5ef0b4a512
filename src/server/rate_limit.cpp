// SPDX-License-Identifier: LGPL-2.1-or-later
#include "rate_limit.hpp"

#include <algorithm>
#include <cmath>

namespace caustic::server {

void RateLimiter::refund(const std::string& address) {
  if (auto it = buckets_.find(address); it != buckets_.end())
    it->second.tokens = std::min(it->second.burst, it->second.tokens + 1.0);
}

bool RateLimiter::admit(const std::string& address, double rate, double burst, int* retry_after_s,
                        Clock::time_point now) {
  // Forget full buckets now and then, so the table stays as small as the
  // set of clients whose buckets are still refilling. A bucket forgotten
  // before it is full would come back full: a design upload's hourly limit
  // was a minute's.
  if (now - last_sweep_ > std::chrono::seconds(60)) {
    for (auto it = buckets_.begin(); it != buckets_.end();) {
      const Bucket& b = it->second;
      const bool full = b.tokens + std::chrono::duration<double>(now - b.last).count() * b.rate >= b.burst;
      it = full ? buckets_.erase(it) : std::next(it);
    }
    last_sweep_ = now;
  }
  auto [it, fresh] = buckets_.try_emplace(address, Bucket{burst, now, rate, burst});
  Bucket& b = it->second;
  if (!fresh) {
    const double elapsed = std::chrono::duration<double>(now - b.last).count();
    b.tokens = std::min(burst, b.tokens + elapsed * rate);
    b.last = now;
    b.rate = rate;
    b.burst = burst;
  }
  if (b.tokens >= 1.0) {
    b.tokens -= 1.0;
    return true;
  }
  if (retry_after_s) *retry_after_s = std::max(1, static_cast<int>(std::ceil((1.0 - b.tokens) / rate)));
  return false;
}

}  // namespace caustic::server
