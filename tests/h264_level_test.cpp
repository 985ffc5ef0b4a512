// SPDX-License-Identifier: LGPL-2.1-or-later
// The H.264 level against ITU-T H.264 Table A-1's limits, worked by hand
// for common sizes: the frame size in macroblocks, macroblocks a second,
// the bit rate and the longest side each push the level up.
#include "h264_level.hpp"

#include <gtest/gtest.h>

namespace caustic::server {
namespace {

TEST(H264Level, IsTheLowestFromThreeOneThatHoldsTheStream) {
  struct Case {
    int width, height, fps, kbps;
    const char* level;
  };
  const Case cases[] = {
      {640, 480, 30, 2000, "3.1"},      // 1,200 macroblocks
      {1280, 720, 30, 2000, "3.1"},     // 3,600 macroblocks, 108,000 a second: 3.1's limits exactly
      {1280, 720, 60, 2000, "3.2"},     // 216,000 a second
      {1280, 720, 30, 16000, "3.2"},    // above 3.1's 14,000 kbit/s
      {1024, 1024, 30, 2000, "3.2"},    // 4,096 macroblocks: above 3.1's 3,600
      {1920, 1080, 30, 4000, "4"},      // 120 x 68 = 8,160 macroblocks, 244,800 a second
      {1920, 1080, 30, 40000, "4.1"},   // above 4's 20,000 kbit/s
      {1920, 1080, 60, 4000, "4.2"},    // 489,600 a second
      {2048, 2048, 30, 4000, "5"},      // 16,384 macroblocks
      {4096, 2304, 30, 8000, "5.2"},    // 36,864 macroblocks, 1,105,920 a second: above 5.1's 983,040
      {4096, 16, 30, 2000, "4"},        // 256 macroblocks, but 256 across: sqrt(8 x 3,600) = 170 for 3.1
  };
  for (const Case& c : cases) {
    const H264Level level = h264_level(c.width, c.height, c.fps, c.kbps);
    EXPECT_EQ(level.name, c.level) << c.width << "x" << c.height << " at " << c.fps << " fps, " << c.kbps << " kbit/s";
    EXPECT_TRUE(level.within);
  }
}

TEST(H264Level, BeyondFiveTwoClaimsFiveTwoAndSaysSo) {
  const H264Level level = h264_level(4096, 4096, 30, 8000);  // 65,536 macroblocks
  EXPECT_EQ(level.name, "5.2");
  EXPECT_FALSE(level.within);
  const std::string warning = h264_level_warning(4096, 4096, 30, 8000);
  for (const char* key : {"width", "height", "framerate", "bitrate_kbps", "4096x4096"})
    EXPECT_NE(warning.find(key), std::string::npos) << warning;
  EXPECT_EQ(h264_level_warning(1024, 1024, 30, 2000), "");
}

TEST(H264Level, ProfileLevelIdEndsInTheLevelIdcInHex) {
  // RFC 6184 8.1: profile_idc, constraint flags, level_idc, two hex digits each.
  EXPECT_EQ(profile_level_id(h264_level(1280, 720, 30, 2000)), "42e01f");
  EXPECT_EQ(profile_level_id(h264_level(1920, 1080, 30, 4000)), "42e028");
  EXPECT_EQ(profile_level_id(h264_level(4096, 2304, 30, 8000)), "42e034");
}

}  // namespace
}  // namespace caustic::server
