// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/jpeg_scans.hpp"

namespace caustic {

std::size_t jpeg_scans(const unsigned char* data, std::size_t size, std::size_t limit) {
  std::size_t scans = 0, pos = 2;  // past SOI
  if (size < 2 || data[0] != 0xff || data[1] != 0xd8) return 0;
  while (pos + 1 < size && scans <= limit) {
    if (data[pos] != 0xff) {  // stray bytes: libjpeg skips them to the next marker, and so does the count
      ++pos;
      continue;
    }
    const unsigned char marker = data[pos + 1];
    if (marker == 0xff) {  // fill byte
      ++pos;
      continue;
    }
    if (marker == 0xd9) return scans;  // EOI
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) {  // no length
      pos += 2;
      continue;
    }
    if (pos + 3 >= size) return scans;
    const std::size_t length = (std::size_t{data[pos + 2]} << 8) | data[pos + 3];
    if (length < 2) return scans;
    pos += 2 + length;
    if (marker != 0xda) continue;
    ++scans;
    // The scan's entropy-coded data: up to the next marker that is neither
    // a stuffed 0xFF (FF 00) nor a restart (FF D0-D7).
    while (pos + 1 < size) {
      if (data[pos] == 0xff && data[pos + 1] != 0x00 && !(data[pos + 1] >= 0xd0 && data[pos + 1] <= 0xd7) &&
          data[pos + 1] != 0xff)
        break;
      ++pos;
    }
  }
  return scans;
}

}  // namespace caustic
