// SPDX-License-Identifier: LGPL-2.1-or-later
// JPEGs from OpenImageIO's own writer (baseline or progressive, with an
// EXIF orientation when asked), and one whose last scan comes again and
// again, as a hostile file repeats it to make the decoder redo its work.
#pragma once

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace caustic::testing {

/// `pixels`: w x h x 3 bytes, rows from the top (grey 128 when empty).
inline std::string jpeg_bytes(int w, int h, bool progressive, int orientation = 0,
                              std::vector<unsigned char> pixels = {}) {
  static int made = 0;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("causticd-jpeg-" + std::to_string(::getpid()) + "-" + std::to_string(made++));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "p.jpg").string();
  auto out = OIIO::ImageOutput::create(file);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  if (progressive) spec.attribute("jpeg:progressive", 1);
  if (orientation) spec.attribute("Orientation", orientation);
  spec.attribute("CompressionQuality", 100);
  if (pixels.empty()) pixels.assign(std::size_t(w) * h * 3, 128);
  EXPECT_TRUE(out->open(file, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove_all(std::filesystem::path(file).parent_path());
  return bytes;
}

/// `jpeg` with its last scan (from its SOS marker to the end before EOI)
/// written `extra` more times.
inline std::string with_last_scan_repeated(const std::string& jpeg, int extra) {
  const std::size_t end = jpeg.rfind("\xff\xd9");
  const std::size_t last = jpeg.rfind("\xff\xda", end);
  EXPECT_NE(last, std::string::npos);
  std::string out = jpeg.substr(0, end);
  const std::string scan = jpeg.substr(last, end - last);
  for (int k = 0; k < extra; ++k) out += scan;
  return out + "\xff\xd9";
}

}  // namespace caustic::testing
