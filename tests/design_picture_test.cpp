// SPDX-License-Identifier: LGPL-2.1-or-later
// Pictures a designer is given as a camera or a hostile file writes them:
// turned by their EXIF orientation, a volume where a picture should be,
// channels beyond colour, a progressive JPEG whose scans never end, and
// files cut short.
#include "caustic/design_target.hpp"
#include "caustic/image_io.hpp"  // Rgba8Image
#include "design_picture_support.hpp"
#include "jpeg_support.hpp"
#include "png_chunk.hpp"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

using namespace caustic;
using namespace caustic::design;
using caustic::testing::animated_png;
using namespace caustic::testing::design_picture;

namespace {

// Mean of channel 0 over [x0, x1) x [y0, y1), rows from the top.
double mean(const RgbHdrImage& image, int x0, int y0, int x1, int y1) {
  double sum = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) sum += image.pixels[3 * (static_cast<std::size_t>(y) * image.width + x)];
  return sum / ((x1 - x0) * (y1 - y0));
}

}  // namespace

TEST(DesignPicture, ACameraPictureIsTurnedAsItsOrientationSays) {
  // Stored 32 x 16, white in its top left 8 x 8 block, black elsewhere; and
  // the same 64 times larger, which is decoded in bands of rows.
  for (const int k : {1, 64}) {
    const int w = 32 * k, h = 16 * k;
    std::vector<unsigned char> pixels(std::size_t(w) * h * 3, 0);
    for (int y = 0; y < 8 * k; ++y)
      for (int x = 0; x < 8 * k; ++x)
        for (int c = 0; c < 3; ++c) pixels[(std::size_t(y) * w + x) * 3 + c] = 255;
    Folder folder;
    // Where the white block is shown (x0, y0 of an 8 x 8 block; the sides swap for 5-8).
    struct Case {
      int orientation, x0, y0;
    };
    for (const Case c : {Case{1, 0, 0}, Case{2, 24, 0}, Case{3, 24, 8}, Case{4, 0, 8}, Case{5, 0, 0}, Case{6, 8, 0},
                         Case{7, 8, 24}, Case{8, 0, 24}}) {
      const auto file = folder.write("o.jpg", caustic::testing::jpeg_bytes(w, h, false, c.orientation, pixels));
      const RgbHdrImage shown = load_target_rgb(file);
      const bool turned = c.orientation >= 5;
      EXPECT_EQ(shown.width, turned ? h : w) << c.orientation;
      EXPECT_EQ(shown.height, turned ? w : h) << c.orientation;
      EXPECT_GT(mean(shown, k * c.x0 + k, k * c.y0 + k, k * c.x0 + 7 * k, k * c.y0 + 7 * k), 0.9)
          << "orientation " << c.orientation << ", " << w << "x" << h;
      EXPECT_LT(mean(shown, 0, 0, shown.width, shown.height), 0.2) << "orientation " << c.orientation;
    }
  }
}

TEST(DesignPicture, AProgressiveJpegOfEndlessScansIsRefusedBeforeItsDecoder) {
  // 140,000 copies of a 4096² picture's last scan held a core for about 40
  // minutes; a hundred are enough to be refused, unread.
  Folder folder;
  const std::string progressive = caustic::testing::jpeg_bytes(64, 64, true);
  EXPECT_EQ(refused(folder.write("p.jpg", progressive)), "accepted");
  const std::string why = refused(folder.write("bomb.jpg", caustic::testing::with_last_scan_repeated(progressive, 100)));
  EXPECT_NE(why.find("scans"), std::string::npos) << why;
  // Named as another format, it is the same file.
  EXPECT_NE(refused(folder.write("bomb.png", caustic::testing::with_last_scan_repeated(progressive, 100))).find("scans"),
            std::string::npos);
}

TEST(DesignPicture, AJpegCutShortIsRefusedNotDesignedWithItsRowsGrey) {
  // Its first half and an end marker: libjpeg fills the rest grey and warns.
  // 1200 a side is decoded in bands of rows, 64 at once.
  Folder folder;
  for (const int side : {64, 1200})
  for (const bool progressive : {false, true}) {
    std::vector<unsigned char> pixels(std::size_t(side) * side * 3);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>((i * 37) % 251);
    const std::string whole = caustic::testing::jpeg_bytes(side, side, progressive, 0, pixels);
    EXPECT_EQ(refused(folder.write("whole.jpg", whole)), "accepted");
    const std::string cut = whole.substr(0, whole.size() / 2) + "\xff\xd9";
    // libjpeg's warnings go to the message, none to stderr (as libpng's did).
    ::testing::internal::CaptureStderr();
    const std::string why = refused(folder.write("cut.jpg", cut));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_NE(why.find("cut short"), std::string::npos) << side << (progressive ? " progressive: " : " baseline: ") << why;
    // With libjpeg's own words: the reader forgot them once asked, and the
    // message said "cut short ()".
    EXPECT_EQ(why.find("()"), std::string::npos) << why;
    // A stray byte after the first segment: libjpeg warns of it alone, and
    // its warning once hid the truncation.
    const std::size_t app0 = cut.find("\xff\xe0"), end = app0 + 4 + 14;  // JFIF's APP0 is 16 bytes long
    ASSERT_EQ(cut.substr(app0 + 2, 2), std::string("\x00\x10", 2));
    const std::string stray = refused(folder.write("stray.jpg", cut.substr(0, end) + std::string(1, '\0') + cut.substr(end)));
    EXPECT_NE(stray.find("damaged or cut short"), std::string::npos) << stray;
  }
}

TEST(DesignPicture, AVolumeIsRefusedAndChannelsBeyondColourAreNotRead) {
  // A DDS volume texture, 8 x 8 x 8 RGBA: its slices were read into a
  // buffer sized for one (the heap overran, the process aborted).
  Folder folder;
  std::string dds = "DDS ";
  const auto u32 = [&](std::uint32_t v) {
    for (int b = 0; b < 4; ++b) dds += static_cast<char>((v >> (8 * b)) & 0xff);
  };
  for (std::uint32_t v : {124u, 0x1u | 0x2u | 0x4u | 0x1000u | 0x800000u, 8u, 8u, 32u, 8u, 0u}) u32(v);
  dds += std::string(44, '\0');
  for (std::uint32_t v : {32u, 0x41u, 0u, 32u, 0x00ff0000u, 0x0000ff00u, 0x000000ffu, 0xff000000u}) u32(v);
  for (std::uint32_t v : {0x1008u, 0x200000u, 0u, 0u, 0u}) u32(v);
  dds += std::string(8 * 8 * 8 * 4, '\xff');
  for (const char* name : {"v.dds", "v.png"}) {
    const std::string why = refused(folder.write(name, dds));
    EXPECT_NE(why.find("volume"), std::string::npos) << name << ": " << why;
  }
  // A picture a pixel wide would leave one pixel of its centre square to
  // design: it is refused as too thin before it is decoded.
  const auto thin = folder.path / "thin.tif";
  auto line = OIIO::ImageOutput::create(thin.string());
  std::vector<unsigned char> white(1 * 400, 255);
  ASSERT_TRUE(line->open(thin.string(), OIIO::ImageSpec(1, 400, 1, OIIO::TypeDesc::UINT8)) &&
              line->write_image(OIIO::TypeDesc::UINT8, white.data()) && line->close());
  EXPECT_NE(refused(thin).find("too thin"), std::string::npos) << refused(thin);
  // Six channels: the first three are the colour, the rest never read.
  const auto tiff = folder.path / "six.tif";
  auto out = OIIO::ImageOutput::create(tiff.string());
  OIIO::ImageSpec spec(16, 16, 6, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> pixels(16 * 16 * 6, 0);
  for (std::size_t p = 0; p < 16 * 16; ++p) pixels[6 * p] = 255, pixels[6 * p + 5] = 255;
  ASSERT_TRUE(out->open(tiff.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  const RgbHdrImage six = load_target_rgb(tiff);
  EXPECT_NEAR(mean(six, 0, 0, 16, 16), 1.0, 1e-6);
  EXPECT_NEAR(six.pixels[1], 0.0, 1e-6);
  EXPECT_NEAR(six.pixels[2], 0.0, 1e-6);
}

TEST(DesignPicture, ATiledPictureReadsAsItsPixels) {
  // A tiled file is decoded a row of tiles at a time, in bands of about a
  // MiB: at 2100 x 300 in colour that is bands of 160 rows at 16-pixel
  // tiles and 128 at 64, so both the band's seam and the last, partial row
  // of tiles (and column: 2100 is no multiple of either) are read. The
  // oracle is the pattern written, each pixel its own value.
  Folder folder;
  const int w = 2100, h = 300;
  const auto value = [](int x, int y, int c) {
    const int n[3] = {(7 * x + 3 * y) % 251, (x + 5 * y) % 253, (x * y) % 241};
    return static_cast<float>(n[c]) / 256.0f;
  };
  std::vector<float> pixels(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) pixels[3 * (static_cast<std::size_t>(y) * w + x) + c] = value(x, y, c);
  for (const auto& [name, tile] : {std::pair{"t16.tif", 16}, {"t64.exr", 64}, {"lines.tif", 0}}) {
    const auto file = folder.path / name;
    auto out = OIIO::ImageOutput::create(file.string());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    spec.tile_width = spec.tile_height = tile;
    ASSERT_TRUE(out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) &&
                out->close()) << name;
    const RgbHdrImage read = load_target_rgb(file);
    ASSERT_EQ(read.width, w);
    ASSERT_EQ(read.height, h);
    std::size_t wrong = 0, first = 0;
    for (std::size_t i = 0; i < pixels.size(); ++i)
      if (std::abs(read.pixels[i] - pixels[i]) > 1e-6f && wrong++ == 0) first = i;
    EXPECT_EQ(wrong, 0u) << name << ": first at pixel " << first / 3 % w << ", row " << first / 3 / w;
  }
}

TEST(DesignPicture, ATileLargerThanThePictureAndTheBoundIsRefusedBeforeItIsDecoded) {
  // A 256 x 256 TIFF in 16-pixel tiles, its tile sizes then raised in its
  // header: decoded, one tile of 32752 a side held 16 GB before libtiff
  // found no data behind it (8192 here: 1 GB should the check fail).
  Folder folder;
  std::string bytes = written_bytes(folder, "tiled.tif", 256, 256, 16, 16);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(refused(folder.path / "tiled.tif"), "accepted");
  // The first IFD's TileWidth (322) and TileLength (323), little-endian
  // SHORT or LONG values in their entries.
  ASSERT_EQ(bytes.substr(0, 2), "II");
  const auto u16 = [&](std::size_t at) { return static_cast<unsigned char>(bytes[at]) | static_cast<unsigned char>(bytes[at + 1]) << 8; };
  const std::size_t ifd = u16(4) | static_cast<std::size_t>(u16(6)) << 16;
  int patched = 0;
  for (int k = 0; k < u16(ifd); ++k) {
    const std::size_t entry = ifd + 2 + 12 * static_cast<std::size_t>(k);
    if (u16(entry) != 322 && u16(entry) != 323) continue;
    bytes[entry + 8] = static_cast<char>(8192 & 0xff), bytes[entry + 9] = static_cast<char>(8192 >> 8);
    if (u16(entry + 2) == 4) bytes[entry + 10] = bytes[entry + 11] = 0;  // LONG
    ++patched;
  }
  ASSERT_EQ(patched, 2);
  const std::string why = refused(folder.write("huge-tiles.tif", bytes));
  EXPECT_NE(why.find("huge-tiles.tif: its tiles of 8192x8192 pixels are larger than the picture and than 4096 a side"),
            std::string::npos) << why;
  // A tile the size of the picture, or a usual one over a small picture, is read.
  for (const auto& [w, h, tile] : {std::tuple{600, 40, 608}, {40, 30, 256}}) {
    const std::string name = "t" + std::to_string(tile) + ".tif";
    ASSERT_FALSE(written_bytes(folder, name, w, h, tile, 16 * ((h + 15) / 16)).empty()) << name;
    EXPECT_EQ(refused(folder.path / name), "accepted") << name;
  }
}

TEST(DesignPicture, ATiffCutShortIsRefusedNotDesignedWithItsRowsBlack) {
  // libtiff says a strip it could not read, and the image library goes on:
  // the rows were black, designed without a word.
  Folder folder;
  const std::string bytes = written_bytes(folder, "whole.tif", 64, 64);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(refused(folder.path / "whole.tif"), "accepted");
  ::testing::internal::CaptureStderr();
  const std::string why = refused(folder.write("cut.tif", bytes.substr(0, bytes.size() / 2)));
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << "libtiff's words go to the message alone";
  EXPECT_NE(why.find("cut.tif: the picture is damaged or cut short ("), std::string::npos) << why;
  EXPECT_NE(why.find("Read error"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
}

TEST(DesignPicture, AFileOfSeveralImagesIsSaidToHaveThemAndItsFirstIsRead) {
  // A multi-page TIFF and an animated GIF: a viewer shows the first page, a
  // browser plays the frames, and only the first was designed, unsaid.
  // Page k is grey (k + 1) / 4 all over: the first reads as 0.25, decoded.
  Folder folder;
  const auto grey = [](int k) { return std::vector<unsigned char>(32 * 32 * 3, static_cast<unsigned char>(64 * (k + 1) - 1)); };
  for (const char* name : {"pages.tif", "frames.gif", "one.tif"}) {
    const int images = std::string(name) == "one.tif" ? 1 : 3;
    const auto file = folder.path / name;
    auto out = OIIO::ImageOutput::create(file.string());
    std::vector<OIIO::ImageSpec> specs(images, OIIO::ImageSpec(32, 32, 3, OIIO::TypeDesc::UINT8));
    ASSERT_TRUE(out && out->open(file.string(), images, specs.data())) << name;
    for (int k = 0; k < images; ++k) {
      if (k > 0) {
        ASSERT_TRUE(out->open(file.string(), specs[k], OIIO::ImageOutput::AppendSubimage)) << name;
      }
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, grey(k).data())) << name;
    }
    ASSERT_TRUE(out->close()) << name;
    std::vector<std::string> warnings;
    const RgbHdrImage read = load_target_rgb(file, &warnings);
    EXPECT_NEAR(mean(read, 0, 0, 32, 32), std::pow((63 / 255.0 + 0.055) / 1.055, 2.4), 0.01) << name;
    if (images == 1) {
      EXPECT_TRUE(warnings.empty()) << name << ": " << warnings.front();
      continue;
    }
    ASSERT_EQ(warnings.size(), 1u) << name;
    EXPECT_EQ(warnings[0], file.string() + ": holds 3 images (pages, frames or parts); only the first is designed");
  }
  // An animated PNG: its reader reads the still image, and the frames are
  // counted by its acTL chunk (3 frames, played for ever).
  const std::string still = png_bytes(folder);
  ASSERT_FALSE(still.empty());
  const std::string animated = animated_png(still, 3);
  std::vector<std::string> warnings;
  const auto apng = folder.write("moving.png", animated);
  load_target_rgb(folder.write("still.png", still), &warnings);
  EXPECT_TRUE(warnings.empty());
  load_target_rgb(apng, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], apng.string() + ": holds 3 images (pages, frames or parts); only the first is designed");
  // Counted up to 100, then said as more: each is a block walked or a seek.
  for (const char* name : {"long.gif", "long.tif"}) {
    const auto file = folder.path / name;
    auto out = OIIO::ImageOutput::create(file.string());
    std::vector<OIIO::ImageSpec> specs(102, OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8));
    const std::vector<unsigned char> white(4 * 4 * 3, 255);
    ASSERT_TRUE(out && out->open(file.string(), 102, specs.data())) << name;
    for (int k = 0; k < 102; ++k) {
      if (k > 0) {
        ASSERT_TRUE(out->open(file.string(), specs[k], OIIO::ImageOutput::AppendSubimage)) << name;
      }
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, white.data())) << name;
    }
    ASSERT_TRUE(out->close()) << name;
    std::vector<std::string> warnings;
    load_target_rgb(file, &warnings);
    ASSERT_EQ(warnings.size(), 1u) << name;
    EXPECT_NE(warnings[0].find(": holds more than 100 images"), std::string::npos) << warnings[0];
  }
}

TEST(DesignPicture, ADarkLogoOnATransparentGroundIsToldWhyItIsBlack) {
  // A black disc on a transparent white ground: taken over black, as light
  // would have it, it is all black; it was refused as "all black" alone,
  // while a viewer shows a black disc on white. The same disc opaque on
  // white is a picture.
  Folder folder;
  for (const bool clear : {true, false}) {
    caustic::Rgba8Image logo{16, 16, std::vector<std::uint8_t>(16 * 16 * 4, 255)};
    int ground = 0;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        std::uint8_t* p = &logo.pixels[(y * 16 + x) * 4];
        if ((x - 8) * (x - 8) + (y - 8) * (y - 8) < 25) p[0] = p[1] = p[2] = 0;
        else if (clear) p[3] = 0, ++ground;
      }
    const auto file = folder.path / (clear ? "clear.png" : "white.png");
    // Written as given: white, not black, under the transparent pixels.
    OIIO::ImageSpec spec(16, 16, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, logo.pixels.data()) &&
                out->close());
    const std::string why = refused(file);
    if (!clear) {
      EXPECT_EQ(why, "accepted");
      continue;
    }
    EXPECT_NE(why.find("clear.png: is all black: its " + std::to_string(ground) + " transparent pixels are taken as black"),
              std::string::npos) << why;
  }
}
