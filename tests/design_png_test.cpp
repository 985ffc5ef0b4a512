// SPDX-License-Identifier: LGPL-2.1-or-later
// A PNG given to the designer: its chunks, checksums, header and image data
// checked before libpng reads it, so that a damaged file is refused in one
// line of its own words and nothing else is printed.
#include "design_picture_support.hpp"
#include "png_chunks.hpp"
#include "png_chunk.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

using namespace caustic::testing::design_picture;
using caustic::testing::png_chunk;
using caustic::testing::png_file;

namespace {

// A PNG that must be refused as damaged, and the words that must say why.
struct Damaged {
  const char* name;
  std::string bytes, reason;
};

// Each refused as damaged or cut short, on one line that names it and its
// reason, with nothing printed besides (libpng's own line would be).
void expect_refused_alone(const Folder& folder, const std::vector<Damaged>& cases) {
  for (const Damaged& c : cases) {
    ::testing::internal::CaptureStderr();
    const std::string why = refused(folder.write(c.name, c.bytes));
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(why.find(std::string(c.name) + ": the picture is damaged or cut short ("), std::string::npos) << why;
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    EXPECT_EQ(said, "") << c.name;
  }
}

}  // namespace

TEST(DesignPicture, APngsPaletteIsCheckedBeforeItsReader) {
  // A palette picture without its palette was libpng's fatal "missing
  // PLTE", on stderr beside the refusal; a palette of the wrong size or a
  // second one its errors, printed as well.
  Folder folder;
  const std::string rows(4 * 5, '\0');  // 4 rows: filter 0, 4 indices 0
  const std::string two_colours = png_chunk("PLTE", std::string("\xff\x00\x00\x00\x00\xff", 6));
  const std::string bad_size = png_chunk("PLTE", std::string("\xff\x00\x00\x00", 4));
  const auto palette = [&](const std::string& before_idat) { return png_file(4, 4, 8, 3, 0, rows, before_idat); };
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(refused(folder.write("palette.png", palette(two_colours))), "accepted");
  // A suggested palette in an RGB picture is PNG's (its 8-bit rows: 4 x 3 bytes).
  const std::string rgb_rows(4 * 13, '\0');
  EXPECT_EQ(refused(folder.write("suggested.png", png_file(4, 4, 8, 2, 0, rgb_rows, two_colours))), "accepted");
  // A palette where PNG has none (a grey picture's, or an RGB picture's
  // after its image data) libpng ignores without a word: read as it is.
  const std::string grey_rows(4 * 5, '\0'), rgb = png_file(4, 4, 8, 2, 0, rgb_rows);
  EXPECT_EQ(refused(folder.write("grey.png", png_file(4, 4, 8, 0, 0, grey_rows, two_colours))), "accepted");
  const std::size_t iend = rgb.size() - 12;
  EXPECT_EQ(refused(folder.write("late.png", rgb.substr(0, iend) + two_colours + rgb.substr(iend))), "accepted");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  expect_refused_alone(folder, {
      Damaged{"paletteless.png", palette(""), "palette picture without its palette: no PLTE chunk before its image data at byte 33"},
      Damaged{"odd-palette.png", palette(bad_size), "its PLTE chunk at byte 33 holds 4 bytes, not 1 to 256 colours of 3"},
      Damaged{"empty-palette.png", palette(png_chunk("PLTE", "")), "holds 0 bytes, not 1 to 256 colours of 3"},
      Damaged{"two-palettes.png", palette(two_colours + two_colours), "it holds a second PLTE chunk at byte 51"},
  });
}

TEST(DesignPicture, APngsImageDataIsCheckedBeforeItsReader) {
  // Chunks whole and checksums right, but the data inside damaged: libpng
  // said "libpng error: ..." on stderr beside the refusal. Now the rows are
  // inflated and counted first, and the refusal alone says why.
  Folder folder;
  const std::string bytes = png_bytes(folder);
  ASSERT_FALSE(bytes.empty());
  const std::size_t idat = bytes.find("IDAT") - 4;
  const std::uint32_t length = static_cast<unsigned char>(bytes[idat]) << 24 |
                               static_cast<unsigned char>(bytes[idat + 1]) << 16 |
                               static_cast<unsigned char>(bytes[idat + 2]) << 8 | static_cast<unsigned char>(bytes[idat + 3]);
  std::string data = bytes.substr(idat + 8, length);
  const std::string head = bytes.substr(0, idat);
  std::string scrambled = data;
  for (std::size_t k = 10; k + 6 < scrambled.size(); ++k) scrambled[k] ^= 0x5a;
  // 5 x 5 grey in Adam7's seven passes, every pixel 7: a row counted from
  // the wrong place reads a 7 as its filter type. Passes 1 to 7 have 1, 1,
  // 1, 2, 1, 3 and 2 rows of 1, 1, 2, 1, 3, 2 and 5 pixels.
  std::string adam7;
  for (const auto& [rows, pixels] : {std::pair{1, 1}, {1, 1}, {1, 2}, {2, 1}, {1, 3}, {3, 2}, {2, 5}})
    for (int r = 0; r < rows; ++r) adam7 += '\0' + std::string(pixels, '\7');
  std::string plain;
  for (int r = 0; r < 5; ++r) plain += '\0' + std::string(5, '\7');
  EXPECT_EQ(refused(folder.write("interlaced.png", png_file(5, 5, 8, 0, 1, adam7))), "accepted");
  EXPECT_EQ(refused(folder.write("plain.png", png_file(5, 5, 8, 0, 0, plain))), "accepted");
  std::string filtered = plain;
  filtered[2 * 6] = 9;  // row 2's filter byte
  expect_refused_alone(folder, {
      Damaged{"scrambled.png", head + png_chunk("IDAT", scrambled) + png_chunk("IEND", ""),
              "its image data does not decompress: zlib says "},
      Damaged{"short.png", head + png_chunk("IDAT", data.substr(0, length / 2)) + png_chunk("IEND", ""),
              "its image data ends after "},
      Damaged{"few-rows.png", png_file(5, 5, 8, 0, 0, plain.substr(0, 18)), "its image data ends after 18 of the 30 bytes"},
      Damaged{"filter.png", png_file(5, 5, 8, 0, 0, filtered), "row 2 has filter type 9, which PNG does not define"},
      Damaged{"interlace-filter.png", png_file(5, 5, 8, 0, 0, adam7), "has filter type 7"},
      Damaged{"depth.png", png_file(5, 5, 4, 2, 0, plain), "its header gives colour type 2 at 4 bits"},
      Damaged{"empty.png", png_file(0, 5, 8, 0, 0, ""), "its header gives a size of 0x5"},
  });
}

TEST(DesignPicture, APngCutShortOrDamagedIsRefusedByItsOwnWordsAlone) {
  // libpng printed its error on stderr itself ("libpng error: IDAT: ...")
  // beside the refusal: the refusal now says why, and nothing else is said.
  Folder folder;
  const std::string bytes = png_bytes(folder);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(refused(folder.write("whole.png", bytes)), "accepted");
  const std::size_t idat = bytes.find("IDAT") - 4, iend = bytes.find("IEND") - 4;
  std::string flipped = bytes;
  flipped[idat + 8 + 100] ^= 0x5a;
  const std::string at = std::to_string(idat);
  expect_refused_alone(folder, {
      Damaged{"half.png", bytes.substr(0, bytes.size() / 2),
              "cut short: the IDAT chunk at byte " + at + " runs past the end of the file"},
      Damaged{"flipped.png", flipped, "the IDAT chunk at byte " + at + " fails its checksum"},
      Damaged{"endless.png", bytes.substr(0, iend),
              "cut short: it ends at byte " + std::to_string(iend) + ", before its IEND chunk"},
      Damaged{"headless.png", bytes.substr(0, 8) + bytes.substr(idat), "does not begin with its IHDR"},
      // The header again (libpng's "IHDR: out of place").
      Damaged{"two-headers.png", bytes.substr(0, 33) + bytes.substr(8, 25) + bytes.substr(33),
              "it holds a second IHDR chunk at byte 33"},
  });
}

TEST(DesignPicture, APngsImageDataEndsWholeInItsFirstIdatChunks) {
  // libpng reads the image data from the first IDAT chunks in a row and on
  // to the zlib stream's end (its checksum checked) after the last row: a
  // stream cut short after its rows, or rows in an IDAT after another
  // chunk, were its fatal "Not enough image data" on stderr.
  Folder folder;
  std::string plain;
  for (int r = 0; r < 5; ++r) plain += '\0' + std::string(5, '\7');
  const std::string z = caustic::testing::zlib_stored(plain);
  const auto with = [&](const std::string& chunks) {
    return png_file(5, 5, 8, 0, 0, plain).substr(0, 33) + chunks + png_chunk("IEND", "");
  };
  const std::string text = png_chunk("tEXt", std::string("Comment\0x", 9));
  // Whole, in three IDATs; a later IDAT after another chunk, and data past
  // the rows, are libpng's warnings only (not printed).
  for (const std::string& bytes :
       {with(png_chunk("IDAT", z.substr(0, 3)) + png_chunk("IDAT", z.substr(3, 20)) + png_chunk("IDAT", z.substr(23))),
        with(png_chunk("IDAT", z) + text + png_chunk("IDAT", "\x03")),
        with(png_chunk("IDAT", caustic::testing::zlib_stored(plain + "\1\2\3")))}) {
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(refused(folder.write("sound.png", bytes)), "accepted");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  }
  expect_refused_alone(folder, {
      Damaged{"checksumless.png", with(png_chunk("IDAT", z.substr(0, z.size() - 4))), "zlib stream is cut short after its rows"},
      Damaged{"half-checksum.png", with(png_chunk("IDAT", z.substr(0, z.size() - 2))), "zlib stream is cut short after its rows"},
      Damaged{"parted.png", with(png_chunk("IDAT", z.substr(0, 20)) + text + png_chunk("IDAT", z.substr(20))),
              "its image data ends after 13 of the 30 bytes"},
  });
}

TEST(DesignPicture, APngsImageDataIsInflatedWithTheWindowItsHeaderGives) {
  // Rows alike 301 bytes apart, compressed with a 32 KiB window, the zlib
  // header then made to say 256 bytes: libpng inflates with the window the
  // header gives and finds "invalid distance too far back" (on stderr).
  // A preset dictionary, which PNG does not allow, is said in words.
  Folder folder;
  std::string row(1, '\0');
  for (std::uint32_t i = 0, x = 12345; i < 300; ++i) row += static_cast<char>((x = x * 1103515245u + 12345u) >> 24);
  const std::string raw = row + row + row;
  std::string z(compressBound(raw.size()), '\0');
  uLongf size = z.size();
  ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9),
            Z_OK);
  z.resize(size);
  const std::string head = png_file(300, 3, 8, 0, 0, raw).substr(0, 33);
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(refused(folder.write("window.png", head + png_chunk("IDAT", z) + png_chunk("IEND", ""))), "accepted");
  z[0] = 0x08, z[1] = 29;  // CINFO 0: a 256-byte window; 0x081d is a multiple of 31
  const std::string narrow = refused(folder.write("narrow.png", head + png_chunk("IDAT", z) + png_chunk("IEND", "")));
  // The same distance within one row, which libpng inflates in one call:
  // zlib lets a call reach back over what it gave itself, and libpng reads.
  const std::string wide = row + row.substr(1) + std::string(601, '\0');
  z.assign(compressBound(wide.size()), '\0');
  size = z.size();
  ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(wide.data()), wide.size(), 9),
            Z_OK);
  z.resize(size);
  z[0] = 0x08, z[1] = 29;
  EXPECT_EQ(refused(folder.write("one-row.png", png_file(600, 2, 8, 0, 0, wide).substr(0, 33) + png_chunk("IDAT", z) +
                                                    png_chunk("IEND", ""))),
            "accepted");
  // FDICT set (0x7820 is a multiple of 31), a dictionary's Adler-32, then rows.
  const std::string stored = caustic::testing::zlib_stored(raw);
  const std::string preset = std::string("\x78\x20\0\0\0\1", 6) + stored.substr(2);
  const std::string dictionary = refused(folder.write("dictionary.png", head + png_chunk("IDAT", preset) + png_chunk("IEND", "")));
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_NE(narrow.find("narrow.png: the picture is damaged or cut short (its image data does not decompress: zlib says "
                        "invalid distance too far back)"),
            std::string::npos)
      << narrow;
  EXPECT_NE(dictionary.find("(its image data asks for a preset dictionary, which PNG does not allow)"), std::string::npos)
      << dictionary;
}

TEST(DesignPicture, APngHeaderBeyondTheBoundLaysOutNoRows) {
  // 1073751857 x 2147463582 at 16-bit RGBA: 2147463582 rows of 8590014857
  // bytes, 2^64 + 536886158 in all, which wrapped to 536886158 and was
  // taken as within a bound of 2^30 (its rows then "missing"). Beyond the
  // bound, nothing is checked; the picture is refused for its size.
  const std::uint32_t w = 1073751857u, h = 2147463582u;
  const unsigned char ihdr[13] = {static_cast<unsigned char>(w >> 24), static_cast<unsigned char>(w >> 16),
                                  static_cast<unsigned char>(w >> 8),  static_cast<unsigned char>(w),
                                  static_cast<unsigned char>(h >> 24), static_cast<unsigned char>(h >> 16),
                                  static_cast<unsigned char>(h >> 8),  static_cast<unsigned char>(h),
                                  16, 6, 0, 0, 0};
  const caustic::design::PngRows rows(ihdr, 1ull << 30);
  EXPECT_EQ(rows.end(), "");
  // Within the bound, the same arithmetic counts every byte.
  const unsigned char small[13] = {0, 0, 0, 5, 0, 0, 0, 5, 16, 6, 0, 0, 1};
  EXPECT_EQ(caustic::design::PngRows(small, 1ull << 30).end(), "its image data ends after 0 of the 211 bytes its header lays out");
}

TEST(DesignPicture, APngBeyondTheSizesIsRefusedForItsSizeBeforeItsReader) {
  // 2,000,000 x 2, whole: libpng refuses a side over a million itself
  // ("Invalid IHDR data", on stderr too) before the designer's size.
  Folder folder;
  const std::string raw(2 * 2000001, '\0');
  std::string z(compressBound(raw.size()), '\0');
  uLongf size = z.size();
  ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9),
            Z_OK);
  z.resize(size);
  const std::string wide = png_file(2000000, 2, 8, 0, 0, "").substr(0, 33) + png_chunk("IDAT", z) + png_chunk("IEND", "");
  // 4096 x 16384 at 16-bit RGBA, Adam7: the largest picture designed, its
  // 30,720 filter bytes beyond the rows' bound once allowed (16,384), so its
  // data went unchecked to libpng ("bad adaptive filter value").
  const std::string adam7 = png_file(4096, 16384, 16, 6, 1, std::string(1, '\x09') + std::string(4096, '\0'));
  ::testing::internal::CaptureStderr();
  const std::string too_wide = refused(folder.write("wide.png", wide));
  const std::string filtered = refused(folder.write("adam7.png", adam7));
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_NE(too_wide.find("wide.png: 2000000x2 pixels is too large"), std::string::npos) << too_wide;
  EXPECT_NE(filtered.find("(row 0 of interlace pass 1 has filter type 9, which PNG does not define)"), std::string::npos)
      << filtered;
}
