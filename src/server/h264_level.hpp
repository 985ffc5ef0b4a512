// SPDX-License-Identifier: LGPL-2.1-or-later
// The H.264 level a stream needs. A decoder sizes its buffers and its pace
// by the level the stream announces (profile-level-id in the SDP, level in
// the encoder's caps): one too low for the frame size or the frame rate is
// a stream the decoder may refuse or drop frames from. Picked from the
// limits of ITU-T H.264 Table A-1, from 3.1 up (the level browsers answer
// by default) to 5.2, the highest WebRTC's decoders take.
#pragma once

#include <string>

namespace caustic::server {

struct H264Level {
  std::string name;  ///< as the encoder's caps write it: "3.1", "4", "5.2"
  int idc;           ///< level_idc: 31, 40, 52; the last byte of profile-level-id
  bool within;       ///< false: beyond 5.2's limits, which the stream then claims anyway
};

/// The lowest level from 3.1 up whose largest frame (in 16 x 16
/// macroblocks, and per side at most the square root of 8 frames' worth),
/// macroblocks a second and bit rate (Baseline, 1000 bits a unit) hold a
/// `width` x `height` stream at `framerate` frames a second and
/// `bitrate_kbps`.
H264Level h264_level(int width, int height, int framerate, int bitrate_kbps);

/// `profile_hex` (42e0: Constrained Baseline) followed by the level's idc in
/// two hex digits: the SDP's profile-level-id.
std::string profile_level_id(const H264Level& level, const std::string& profile_hex = "42e0");

/// A warning naming the keys when an H.264 stream of this size, rate and
/// bit rate is beyond level 5.2 (it then claims 5.2, which decoders may
/// refuse); empty otherwise.
std::string h264_level_warning(int width, int height, int framerate, int bitrate_kbps);

}  // namespace caustic::server
