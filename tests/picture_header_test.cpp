// SPDX-License-Identifier: LGPL-2.1-or-later
// The upload sniffer on its own: sizes read from real encoder output (not
// from the sniffer's idea of the format), and headers cut or forged.
#include "picture_header.hpp"

#include "caustic/image_io.hpp"
#include "caustic/jpeg_markers.hpp"
#include "caustic/jpeg_scans.hpp"
#include "jpeg_support.hpp"

#include <OpenImageIO/imageio.h>

#include <glib.h>
#include <unistd.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace caustic::server {
namespace {

using caustic::testing::jpeg_bytes;
using caustic::testing::with_last_scan_repeated;

PictureHeader sniff(const std::string& bytes) {
  return read_picture_header(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
}

TEST(PictureHeader, ReadsThePngEncodersSize) {
  const auto png = encode_png(Rgba8Image{37, 21, std::vector<std::uint8_t>(37 * 21 * 4, 200)});
  const PictureHeader h = read_picture_header(png.data(), png.size());
  EXPECT_EQ(h.format, PictureHeader::Format::png);
  EXPECT_EQ(h.width, 37u);
  EXPECT_EQ(h.height, 21u);
  // Cut inside IHDR: the format is known, the size is not.
  const PictureHeader cut = read_picture_header(png.data(), 20);
  EXPECT_EQ(cut.format, PictureHeader::Format::png);
  EXPECT_EQ(cut.width, 0u);
}

TEST(PictureHeader, ReadsBaselineAndProgressiveJpegSizes) {
  for (const bool progressive : {false, true}) {
    const PictureHeader h = sniff(jpeg_bytes(50, 30, progressive));
    EXPECT_EQ(h.format, PictureHeader::Format::jpeg);
    EXPECT_EQ(h.width, 50u) << progressive;
    EXPECT_EQ(h.height, 30u) << progressive;
  }
  // Cut before the frame header, or a segment length that runs off the end.
  const std::string jpeg = jpeg_bytes(50, 30, false);
  EXPECT_EQ(sniff(jpeg.substr(0, 6)).width, 0u);
  EXPECT_EQ(sniff(std::string("\xff\xd8\xff\xe0\xff\xff", 6)).width, 0u);
  EXPECT_EQ(sniff(std::string("\xff\xd8\xff\xe0\x00\x01", 6)).width, 0u);  // length below 2
}

TEST(PictureHeader, AnythingElseIsUnknown) {
  for (const std::string& bytes : {std::string(), std::string("GIF89a"), std::string("\x89PNX\r\n\x1a\n", 8),
                                   std::string("\xff\xd8", 2), std::string("RIFF\0\0\0\0WEBP", 12)})
    EXPECT_EQ(sniff(bytes).format, PictureHeader::Format::unknown) << bytes.size();
  // A PNG whose first chunk is not IHDR has no size.
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDX\0\0\0\x10\0\0\0\x10", 24);
  EXPECT_EQ(sniff(png).width, 0u);
  png[15] = 'R';
  EXPECT_EQ(sniff(png).width, 16u);
  // Sizes beyond what PNG allows.
  png[16] = '\x80';
  EXPECT_EQ(sniff(png).width, 0u);
}

TEST(PictureHeader, APictureCutShortIsSeenFromItsEnd) {
  const auto png_vec = encode_png(Rgba8Image{37, 21, std::vector<std::uint8_t>(37 * 21 * 4, 200)});
  const std::string png(png_vec.begin(), png_vec.end()), jpeg = jpeg_bytes(64, 48, false);
  const auto complete = [](const std::string& bytes, PictureHeader::Format f) {
    return picture_complete(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), f);
  };
  EXPECT_TRUE(complete(png, PictureHeader::Format::png));
  EXPECT_TRUE(complete(jpeg, PictureHeader::Format::jpeg));
  EXPECT_TRUE(complete(jpeg + "trailing", PictureHeader::Format::jpeg));  // bytes after the end marker are common
  for (const std::size_t keep : {std::size_t{0}, std::size_t{12}, png.size() / 2, png.size() - 1})
    EXPECT_FALSE(complete(png.substr(0, keep), PictureHeader::Format::png)) << keep;
  for (const std::size_t keep : {std::size_t{0}, std::size_t{2}, jpeg.size() / 2, jpeg.size() - 1})
    EXPECT_FALSE(complete(jpeg.substr(0, keep), PictureHeader::Format::jpeg)) << keep;
  EXPECT_FALSE(complete(png, PictureHeader::Format::unknown));
}

TEST(JpegScans, AreCountedThroughSegmentsAndEntropyCodedData) {
  const auto count = [](const std::string& bytes, std::size_t limit = kMaxJpegScans) {
    return jpeg_scans(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), limit);
  };
  EXPECT_EQ(count(jpeg_bytes(64, 48, false)), 1u);
  const std::string progressive = jpeg_bytes(64, 48, true);
  const std::size_t scans = count(progressive);
  EXPECT_GT(scans, 1u);
  EXPECT_LE(scans, 16u);
  // Its last scan again 100 times: past the limit, and the walk stops there.
  const std::string bomb = with_last_scan_repeated(progressive, 100);
  EXPECT_EQ(count(bomb), kMaxJpegScans + 1);
  EXPECT_EQ(count(bomb, 1000), scans + 100);
  // A stray byte after a segment, skipped by libjpeg: it hid every scan from the count.
  const std::size_t app0 = bomb.find("\xff\xe0");
  ASSERT_NE(app0, std::string::npos);
  const std::size_t after_app0 = app0 + 2 + ((std::size_t(std::uint8_t(bomb[app0 + 2])) << 8) | std::uint8_t(bomb[app0 + 3]));
  const std::string stray = bomb.substr(0, after_app0) + std::string(1, '\0') + bomb.substr(after_app0);
  EXPECT_EQ(count(stray), kMaxJpegScans + 1);
  // Cut anywhere, or not a JPEG: counted as far as it goes, never past the end.
  for (std::size_t cut = 0; cut < progressive.size(); cut += 7) EXPECT_LE(count(progressive.substr(0, cut)), scans);
  EXPECT_EQ(count("not a jpeg at all"), 0u);
}

TEST(JpegMarkers, WalkAnEncodersFileFromSegmentToSegmentToItsEnd) {
  const std::string jpeg = jpeg_bytes(50, 30, false);
  JpegMarkers markers(reinterpret_cast<const unsigned char*>(jpeg.data()), jpeg.size());
  std::string seen;
  std::size_t last = 0;
  while (const auto segment = markers.next()) {
    EXPECT_GT(segment->at, last);
    EXPECT_EQ(std::uint8_t(jpeg[segment->at]), 0xffu);
    last = segment->at;
    char hex[4];
    std::snprintf(hex, sizeof hex, "%02X ", segment->marker);
    seen += hex;
  }
  // JFIF (APP0), tables, the baseline frame, one scan, the end (ITU T.81 B.2).
  EXPECT_EQ(seen.substr(0, 3), "E0 ") << seen;
  EXPECT_NE(seen.find("C0 "), std::string::npos) << seen;
  EXPECT_LT(seen.find("C0 "), seen.find("DA ")) << seen;
  EXPECT_EQ(seen.find("DA "), seen.rfind("DA ")) << seen;
  EXPECT_EQ(seen.substr(seen.size() - 3), "D9 ") << seen;
  EXPECT_EQ(last, jpeg.size() - 2);
}

TEST(PictureHeader, AStrayByteBeforeTheFrameIsSkippedAsTheDecoderSkipsIt) {
  // The size read is the one libjpeg (through OpenImageIO) decodes: the
  // header check and the decoder walk the same markers.
  const std::string jpeg = jpeg_bytes(50, 30, false);
  const std::size_t app0 = jpeg.find("\xff\xe0");
  ASSERT_NE(app0, std::string::npos);
  const std::size_t after = app0 + 2 + ((std::size_t(std::uint8_t(jpeg[app0 + 2])) << 8) | std::uint8_t(jpeg[app0 + 3]));
  const std::string stray = jpeg.substr(0, after) + std::string(1, '\0') + jpeg.substr(after);
  const PictureHeader h = sniff(stray);
  EXPECT_EQ(h.width, 50u);
  EXPECT_EQ(h.height, 30u);
  const std::filesystem::path file = std::filesystem::temp_directory_path() / ("picture_header_stray-" + std::to_string(::getpid()) + ".jpg");
  std::ofstream(file, std::ios::binary) << stray;
  auto in = OIIO::ImageInput::open(file.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(in->spec().width, 50);
  EXPECT_EQ(in->spec().height, 30);
  std::vector<unsigned char> pixels(50 * 30 * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data())) << in->geterror();
  in->close();
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace caustic::server
