// SPDX-License-Identifier: LGPL-2.1-or-later
// read_picture_header sees the first bytes of every uploaded picture before
// anything decodes it. Whatever comes in, it reads only what it was given
// (ASan), and a size comes only with a known format, both sides non-zero.
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
  return 0;
}
