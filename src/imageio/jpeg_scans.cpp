// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/jpeg_scans.hpp"

#include "caustic/jpeg_markers.hpp"

namespace caustic {

std::size_t jpeg_scans(const unsigned char* data, std::size_t size, std::size_t limit) {
  std::size_t scans = 0;
  JpegMarkers markers(data, size);
  while (scans <= limit) {
    const auto segment = markers.next();
    if (!segment || segment->marker == 0xd9) break;  // the end of the data, or EOI
    if (segment->marker == 0xda) ++scans;
  }
  return scans;
}

}  // namespace caustic
