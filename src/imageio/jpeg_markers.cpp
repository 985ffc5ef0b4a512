// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/jpeg_markers.hpp"

namespace caustic {
namespace {

bool standalone(unsigned char marker) { return marker == 0x01 || (marker >= 0xd0 && marker <= 0xd9); }

}  // namespace

JpegMarkers::JpegMarkers(const unsigned char* data, std::size_t size) : data_(data), size_(size) {
  if (size < 2 || data[0] != 0xff || data[1] != 0xd8) size_ = 0;  // no SOI: no markers
}

std::optional<JpegMarkers::Segment> JpegMarkers::next() {
  if (in_scan_) {
    // Entropy-coded data runs to the next 0xFF that is neither stuffed
    // (FF 00), a restart (FF D0-D7) nor a fill byte.
    while (pos_ + 1 < size_ &&
           !(data_[pos_] == 0xff && data_[pos_ + 1] != 0x00 && data_[pos_ + 1] != 0xff &&
             !(data_[pos_ + 1] >= 0xd0 && data_[pos_ + 1] <= 0xd7)))
      ++pos_;
    in_scan_ = false;
  }
  while (pos_ + 1 < size_) {
    if (data_[pos_] != 0xff || data_[pos_ + 1] == 0xff) {  // a stray byte, or a fill byte before the marker
      ++pos_;
      continue;
    }
    const Segment segment{data_[pos_ + 1], pos_, 0};
    if (standalone(segment.marker)) {
      pos_ += 2;
      return segment;
    }
    if (pos_ + 3 >= size_) break;
    const std::size_t length = (std::size_t{data_[pos_ + 2]} << 8) | data_[pos_ + 3];
    if (length < 2) break;
    pos_ += 2 + length;
    in_scan_ = segment.marker == 0xda;
    return Segment{segment.marker, segment.at, length};
  }
  pos_ = size_;
  return std::nullopt;
}

}  // namespace caustic
