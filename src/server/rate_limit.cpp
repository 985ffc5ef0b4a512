// SPDX-License-Identifier: LGPL-2.1-or-later
#include "rate_limit.hpp"

#include <cmath>

namespace caustic::server {

bool RateLimiter::admit(const std::string& address, double rate, double burst, int* retry_after_s,
                        Clock::time_point now) {
  // Forget full buckets now and then, so the table stays as small as the
  // set of clients that were busy within the last minute.
  if (now - last_sweep_ > std::chrono::seconds(60)) {
    for (auto it = buckets_.begin(); it != buckets_.end();)
      it = now - it->second.last > std::chrono::seconds(60) ? buckets_.erase(it) : std::next(it);
    last_sweep_ = now;
  }
  auto [it, fresh] = buckets_.try_emplace(address, Bucket{burst, now});
  Bucket& b = it->second;
  if (!fresh) {
    const double elapsed = std::chrono::duration<double>(now - b.last).count();
    b.tokens = std::min(burst, b.tokens + elapsed * rate);
    b.last = now;
  }
  if (b.tokens >= 1.0) {
    b.tokens -= 1.0;
    return true;
  }
  if (retry_after_s) *retry_after_s = std::max(1, static_cast<int>(std::ceil((1.0 - b.tokens) / rate)));
  return false;
}

}  // namespace caustic::server
