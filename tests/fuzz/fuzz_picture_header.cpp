// SPDX-License-Identifier: LGPL-2.1-or-later
// read_picture_header sees the first bytes of every uploaded picture before
// anything decodes it, and the JPEG marker walk under it counts a JPEG's
// scans too. Whatever comes in, they read only what they were given
// (ASan), a size comes only with a known format, both sides non-zero, and
// the walk moves forward from marker to marker and ends.
#include "caustic/jpeg_markers.hpp"
#include "caustic/jpeg_scans.hpp"
#include "picture_header.hpp"
#include "fuzz_support.hpp"

#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace s = caustic::server;
  const s::PictureHeader h = s::read_picture_header(data, size);
  if (h.width || h.height) {
    FUZZ_CHECK(h.format != s::PictureHeader::Format::unknown);
    FUZZ_CHECK(h.width > 0 && h.height > 0);
  }
  if (h.format == s::PictureHeader::Format::png) FUZZ_CHECK(size >= 8 && data[0] == 0x89);
  if (h.format == s::PictureHeader::Format::jpeg) FUZZ_CHECK(size >= 3 && data[0] == 0xff && data[1] == 0xd8);
  caustic::JpegMarkers markers(data, size);
  std::size_t last = 1, count = 0;
  while (const auto segment = markers.next()) {
    FUZZ_CHECK(segment->at > last && segment->at + 1 < size);
    FUZZ_CHECK(data[segment->at] == 0xff && data[segment->at + 1] == segment->marker);
    FUZZ_CHECK(segment->length == 0 || segment->length >= 2);
    last = segment->at;
    FUZZ_CHECK(++count <= size / 2);
  }
  FUZZ_CHECK(caustic::jpeg_scans(data, size) <= caustic::kMaxJpegScans + 1);
  return 0;
}
