// SPDX-License-Identifier: LGPL-2.1-or-later
// Token buckets per client address: each request that changes something
// takes a token, tokens come back at `rate` a second up to `burst`. A drag
// in the viewer sends a PATCH per animation frame (30-60 a second), so the
// defaults leave it alone while a loop hammering the API is slowed to 429s.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace caustic::server {

class RateLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  /// True when `address` may go ahead (a token is taken); otherwise
  /// `*retry_after_s` says when the next token is due (whole seconds, >= 1).
  bool admit(const std::string& address, double rate, double burst, int* retry_after_s,
             Clock::time_point now = Clock::now());

  /// Gives back the token admit() took from `address` for a request that
  /// then did nothing (up to its bucket's burst).
  void refund(const std::string& address);

 private:
  struct Bucket {
    double tokens;
    Clock::time_point last;
    double rate, burst;  // as last asked: when the bucket is full again
  };
  std::map<std::string, Bucket> buckets_;
  Clock::time_point last_sweep_{};
};

}  // namespace caustic::server
