// SPDX-License-Identifier: LGPL-2.1-or-later
#include "h264_level.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>

namespace caustic::server {
namespace {

struct Limits {
  const char* name;
  int idc;
  std::int64_t max_mbps, max_fs, max_br;  // macroblocks a second, macroblocks a frame, kbit/s
};

// ITU-T H.264 (08/2021) Table A-1, levels 3.1 to 5.2. 4.1 differs from 4
// only in bit rate, 5.2 from 5.1 only in macroblocks a second.
constexpr Limits kLevels[] = {
    {"3.1", 31, 108000, 3600, 14000},    {"3.2", 32, 216000, 5120, 20000},   {"4", 40, 245760, 8192, 20000},
    {"4.1", 41, 245760, 8192, 50000},    {"4.2", 42, 522240, 8704, 50000},   {"5", 50, 589824, 22080, 135000},
    {"5.1", 51, 983040, 36864, 240000},  {"5.2", 52, 2073600, 36864, 240000},
};

}  // namespace

H264Level h264_level(int width, int height, int framerate, int bitrate_kbps) {
  const std::int64_t across = (width + 15) / 16, down = (height + 15) / 16, frame = across * down;
  for (const Limits& l : kLevels) {
    // A.3.1 (f): neither side may exceed sqrt(8 MaxFS) macroblocks.
    const double side = std::sqrt(8.0 * static_cast<double>(l.max_fs));
    if (frame <= l.max_fs && across <= side && down <= side && frame * framerate <= l.max_mbps &&
        bitrate_kbps <= l.max_br)
      return {l.name, l.idc, true};
  }
  const Limits& top = kLevels[std::size(kLevels) - 1];
  return {top.name, top.idc, false};
}

std::string profile_level_id(const H264Level& level, const std::string& profile_hex) {
  char idc[3];
  std::snprintf(idc, sizeof idc, "%02x", static_cast<unsigned>(level.idc) & 0xffu);
  return profile_hex + idc;
}

std::string h264_level_warning(int width, int height, int framerate, int bitrate_kbps) {
  if (h264_level(width, height, framerate, bitrate_kbps).within) return "";
  return "width, height, framerate, bitrate_kbps: an H.264 stream of " + std::to_string(width) + "x" +
         std::to_string(height) + " at " + std::to_string(framerate) + " fps and " + std::to_string(bitrate_kbps) +
         " kbit/s is beyond level 5.2, the highest browsers decode: H.264 sessions claim 5.2 and may be refused (VP8 "
         "has no such limit)";
}

}  // namespace caustic::server
