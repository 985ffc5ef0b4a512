// SPDX-License-Identifier: LGPL-2.1-or-later
// The token buckets of the request and upload limits, on a clock the test
// sets: a bucket refills at its rate up to its burst, and one forgotten by
// the table's sweep is one that was full again, never one still refilling.
#include "address_group.hpp"
#include "rate_limit.hpp"

#include <gtest/gtest.h>

using caustic::server::address_group;
using caustic::server::RateLimiter;
using namespace std::chrono_literals;

TEST(RateLimiter, ABucketRefillsAtItsRateUpToItsBurst) {
  RateLimiter limiter;
  const auto t0 = RateLimiter::Clock::time_point{} + 1000h;
  int retry = 0;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(limiter.admit("a", 1.0, 3.0, &retry, t0)) << i;
  EXPECT_FALSE(limiter.admit("a", 1.0, 3.0, &retry, t0));
  EXPECT_EQ(retry, 1);
  EXPECT_TRUE(limiter.admit("b", 1.0, 3.0, &retry, t0)) << "another address has its own bucket";
  EXPECT_TRUE(limiter.admit("a", 1.0, 3.0, &retry, t0 + 1s));
  EXPECT_FALSE(limiter.admit("a", 1.0, 3.0, &retry, t0 + 1s));
}

TEST(RateLimiter, AnHourlyLimitIsNotForgottenAfterAMinute) {
  // 20 an hour, 4 at once: the table's sweep (every minute) forgot every
  // bucket idle a minute, so 4 more came every two minutes instead of 20 an hour.
  RateLimiter limiter;
  const auto t0 = RateLimiter::Clock::time_point{} + 1000h;
  const double rate = 20.0 / 3600, burst = 4;
  int retry = 0, admitted = 0;
  for (int minute = 0; minute < 30; minute += 2)
    for (int i = 0; i < 4; ++i)
      admitted += limiter.admit("a", rate, burst, &retry, t0 + std::chrono::minutes(minute) + std::chrono::seconds(i));
  // The burst, then one every three minutes: 4 + 9 in the 28 minutes.
  EXPECT_LE(admitted, 4 + 10);
  EXPECT_GE(admitted, 4 + 8);
  // Full again after its refill time, the bucket is forgotten and comes back full.
  const auto later = t0 + 3h;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(limiter.admit("a", rate, burst, &retry, later)) << i;
  EXPECT_FALSE(limiter.admit("a", rate, burst, &retry, later));
}

TEST(AddressGroup, AnIpv6ClientCountsAsItsSlash64AndIpv4AsItself) {
  // A subscriber's /64 is its own to roam: counted address by address, every
  // limit per address fell to a client that took a fresh one each time.
  EXPECT_EQ(address_group("2001:db8:1:2:3:4:5:6"), "2001:db8:1:2::/64");
  EXPECT_EQ(address_group("2001:db8:1:2:ffff::1"), address_group("2001:db8:1:2::7"));
  EXPECT_NE(address_group("2001:db8:1:3::1"), address_group("2001:db8:1:2::1"));
  EXPECT_EQ(address_group("::1"), "::/64");
  EXPECT_EQ(address_group("192.0.2.1"), "192.0.2.1");
  EXPECT_NE(address_group("192.0.2.1"), address_group("192.0.2.2"));
  EXPECT_EQ(address_group("::ffff:192.0.2.1"), "192.0.2.1");  // a dual-stack socket's IPv4 client
  EXPECT_EQ(address_group("unknown"), "unknown");
}
