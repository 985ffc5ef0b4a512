// SPDX-License-Identifier: LGPL-2.1-or-later
// A PNG's chunks walked, their checksums checked, and its image data
// inflated and its rows' filter bytes read, before its reader sees it:
// libpng prints each error on stderr itself ("libpng error: ...") beside
// the one line the refusal says, and the image library gives it no way to
// be quiet. A file cut short, with a damaged byte, or whose compressed data
// is damaged or ends before its rows do, fails here, named; libpng then
// reads only whole files.
#pragma once

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace caustic::design {

// The CRC-32 of ISO 3309 that every PNG chunk ends with (PNG spec, annex D).
inline std::uint32_t png_crc(std::uint32_t crc, const unsigned char* bytes, std::size_t n) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ bytes[i]) & 0xff] ^ (crc >> 8);
  return crc;
}

/// The big-endian 32-bit number at `p`: a PNG's lengths, sizes and checksums.
inline std::uint32_t png_be32(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}

/// A PNG's image data as its header lays it out, checked as it is
/// inflated: each row's filter byte (0 to 4), and that the zlib stream is
/// whole and holds every row. Rows of each interlace pass in turn (Adam7),
/// or of the one image.
class PngRows {
 public:
  /// From the IHDR chunk's 13 bytes; inert (checks nothing) when they are
  /// not a header libpng would take, or the rows would exceed `max_bytes`
  /// (a header beyond the designer's sizes, refused from its size later).
  PngRows(const unsigned char* ihdr, std::uint64_t max_bytes) {
    const auto be = [&](int at) { return png_be32(ihdr + at); };
    const std::uint64_t w = be(0), h = be(4);
    const int depth = ihdr[8], type = ihdr[9], interlace = ihdr[12];
    const int samples = type == 0 || type == 3 ? 1 : type == 2 ? 3 : type == 4 ? 2 : type == 6 ? 4 : 0;
    if (!w || !h || !samples || (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16) || interlace > 1)
      return;
    // Each pass's first column and row, and its steps across and down.
    static const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4}, {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    static const int whole[4] = {0, 0, 1, 1};
    std::uint64_t total = 0;
    for (int p = 0; p < (interlace ? 7 : 1); ++p) {
      const int* a = interlace ? adam7[p] : whole;
      const std::uint64_t pw = w > std::uint64_t(a[0]) ? (w - a[0] + a[2] - 1) / a[2] : 0;
      const std::uint64_t ph = h > std::uint64_t(a[1]) ? (h - a[1] + a[3] - 1) / a[3] : 0;
      if (!pw || !ph) continue;  // an empty pass has no rows, not even filter bytes
      const std::uint64_t row_bytes = 1 + (pw * samples * depth + 7) / 8;  // at most 2^35
      // Compared before it is multiplied: rows of 2^35 bytes 2^32 times
      // over wrap past 2^64, and a header of 2^31 x 2^30 would lay out a
      // few hundred megabytes, within the bound.
      if (ph > (max_bytes - total) / row_bytes) {
        passes_.clear();
        return;
      }
      passes_.push_back({ph, row_bytes});
      total += ph * row_bytes;
    }
    expected_ = total;
    // Room for a whole row, as libpng's row buffer (every row the designer
    // takes fits; a wider one is inflated in pieces).
    for (const Pass& pass : passes_) out_.resize(std::clamp<std::uint64_t>(pass.row_bytes, out_.size(), 1 << 20));
    // With the window the stream's header gives (windowBits 0), as libpng
    // inflates it: a distance past it is libpng's "too far back".
    active_ = inflateInit2(&zs_, 0) == Z_OK;
  }
  ~PngRows() {
    if (active_) inflateEnd(&zs_);
  }
  PngRows(const PngRows&) = delete;
  PngRows& operator=(const PngRows&) = delete;

  /// A piece of the IDAT chunks' data, in order, as libpng reads it (at
  /// most kInputPiece bytes, from an IDAT's start); "" or why it is damaged.
  /// Inflated to the stream's end, past the rows: libpng reads on to it
  /// (and checks its Adler-32) once the last row is read, and a stream that
  /// stops short of it is its fatal "Not enough image data". What follows
  /// the rows (more data, an extra block) is only libpng's warning.
  std::string feed(const unsigned char* data, std::size_t n) {
    if (!active_ || ended_) return "";
    zs_.next_in = const_cast<unsigned char*>(data);
    zs_.avail_in = static_cast<uInt>(n);
    while (zs_.avail_in > 0 && !ended_) {
      // Asked for as libpng asks: the rest of the row, then 1024 bytes at a
      // time past the rows. zlib finds a distance too far back from where
      // each call began, so other pieces would judge some streams otherwise.
      const std::uint64_t want = produced_ < expected_ ? passes_[pass_].row_bytes - at_ : 1024;
      zs_.next_out = out_.data();
      zs_.avail_out = static_cast<uInt>(std::min<std::uint64_t>(want, out_.size()));
      const int r = inflate(&zs_, Z_NO_FLUSH);
      if (r == Z_NEED_DICT) return "its image data asks for a preset dictionary, which PNG does not allow";
      if (r != Z_OK && r != Z_STREAM_END && r != Z_BUF_ERROR)
        return std::string("its image data does not decompress: zlib says ") + (zs_.msg ? zs_.msg : "error " + std::to_string(r));
      if (const std::string why = read_rows(zs_.next_out - out_.data()); !why.empty()) return why;
      if (r == Z_STREAM_END) ended_ = true;
      if (r == Z_BUF_ERROR) break;
    }
    return "";
  }
  /// Once the IDAT chunks end (the first chunk after them, or IEND): ""
  /// when every row came and the stream ended whole.
  std::string end() const {
    if (!active_) return "";
    if (produced_ < expected_)
      return "its image data ends after " + std::to_string(produced_) + " of the " + std::to_string(expected_) +
             " bytes its header lays out";
    if (!ended_) return "its image data's zlib stream is cut short after its rows (its end or its checksum is missing)";
    return "";
  }

  /// libpng's IDAT reads (PNG_IDAT_READ_SIZE).
  static constexpr std::size_t kInputPiece = 8192;

 private:
  std::string read_rows(std::size_t n) {
    for (std::size_t i = 0; i < n && produced_ < expected_; ++i, ++produced_) {
      if (at_ == 0 && out_[i] > 4)
        return "row " + std::to_string(row_) + (passes_.size() > 1 ? " of interlace pass " + std::to_string(pass_ + 1) : "") +
               " has filter type " + std::to_string(out_[i]) + ", which PNG does not define";
      if (++at_ == passes_[pass_].row_bytes) {
        at_ = 0;
        if (++row_ == passes_[pass_].rows) row_ = 0, ++pass_;
      }
    }
    return "";
  }
  struct Pass {
    std::uint64_t rows, row_bytes;
  };
  std::vector<Pass> passes_;
  std::uint64_t expected_ = 0, produced_ = 0, at_ = 0, row_ = 0;
  std::size_t pass_ = 0;
  z_stream zs_{};
  bool active_ = false, ended_ = false;
  std::vector<unsigned char> out_ = std::vector<unsigned char>(1 << 16);
};

/// Why a PNG's IHDR chunk (its 13 bytes) is not one the PNG spec defines
/// (section 11.2.2), or "": sizes, bit depth for the colour type, methods.
inline std::string png_header_fault(const unsigned char* ihdr) {
  const auto be = [&](int at) { return png_be32(ihdr + at); };
  const int depth = ihdr[8], type = ihdr[9];
  if (be(0) == 0 || be(4) == 0 || be(0) > 0x7fffffffu || be(4) > 0x7fffffffu)
    return "its header gives a size of " + std::to_string(be(0)) + "x" + std::to_string(be(4)) + ", which PNG does not allow";
  const bool depth_fits = type == 0   ? depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16
                          : type == 3 ? depth == 1 || depth == 2 || depth == 4 || depth == 8
                          : type == 2 || type == 4 || type == 6 ? depth == 8 || depth == 16
                                                                 : false;
  if (!depth_fits)
    return "its header gives colour type " + std::to_string(type) + " at " + std::to_string(depth) +
           " bits, which PNG does not define";
  if (ihdr[10] != 0 || ihdr[11] != 0 || ihdr[12] > 1)
    return "its header names a compression, filter or interlace method PNG does not define";
  return "";
}

/// Why the PNG read from `in` is damaged, in words for a message; "" when
/// its chunks are whole, each checksum right, and an IEND ends them, or
/// when it is no PNG at all (its own reader judges it). An animated PNG's
/// frame count (its acTL chunk's) goes to `frames`, which is left as it is
/// for any other. Its rows are checked (PngRows) when they take at most
/// `max_row_bytes`.
inline std::string png_damage(std::istream& in, std::uint32_t* frames = nullptr, std::uint64_t max_row_bytes = 1ull << 32) {
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char head[8] = {};
  if (!in.read(reinterpret_cast<char*>(head), 8) || !std::equal(head, head + 8, signature)) return "";
  std::vector<unsigned char> data(1 << 16);
  std::unique_ptr<PngRows> rows;
  std::string header, inflated;  // what the header and the image data's inflation have wrong
  // libpng reads the image data from the first IDAT chunks in a row alone:
  // its stream must end there, and a later IDAT is only its warning.
  bool idat_seen = false, idat_over = false;
  // libpng's fatal "missing PLTE", "invalid" and "duplicate" (PNG 11.2.3).
  // A palette in a grey picture, or after an RGB picture's image data,
  // libpng ignores without a word, and so does this.
  int colour_type = -1;
  bool palette_seen = false;
  for (std::uint64_t at = 8, chunks = 0;; ++chunks) {
    if (!in.read(reinterpret_cast<char*>(head), 8))
      return "cut short: it ends at byte " + std::to_string(at) + ", before its IEND chunk";
    const std::uint32_t length = png_be32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    for (const char c : type)
      if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')))
        return "byte " + std::to_string(at) + " holds no chunk";
    if (chunks == 0 && type != "IHDR") return "it does not begin with its IHDR chunk";
    if (length > 0x7fffffffu) return "the " + type + " chunk at byte " + std::to_string(at) + " claims " +
                                     std::to_string(length) + " bytes, more than PNG allows";
    std::uint32_t crc = png_crc(0xffffffffu, head + 4, 4);
    for (std::uint32_t left = length; left > 0;) {
      const std::uint32_t n = std::min<std::uint32_t>(left, static_cast<std::uint32_t>(data.size()));
      if (!in.read(reinterpret_cast<char*>(data.data()), n))
        return "cut short: the " + type + " chunk at byte " + std::to_string(at) + " runs past the end of the file";
      crc = png_crc(crc, data.data(), n);
      if (type == "IHDR" && chunks == 0 && left == length && n >= 13) {
        header = png_header_fault(data.data());
        colour_type = data[9];
        rows = std::make_unique<PngRows>(data.data(), max_row_bytes);
      }
      // Said once the checksum is right: a damaged byte is the first cause.
      // The pieces libpng reads: `data` holds a whole number of them.
      if (type == "IDAT" && rows && !idat_over)
        for (std::uint32_t k = 0; k < n && inflated.empty(); k += PngRows::kInputPiece)
          inflated = rows->feed(data.data() + k, std::min<std::size_t>(PngRows::kInputPiece, n - k));
      if (type == "acTL" && left == length && n >= 4 && frames)
        *frames = png_be32(data.data());
      left -= n;
    }
    unsigned char stored[4] = {};
    if (!in.read(reinterpret_cast<char*>(stored), 4))
      return "cut short: the " + type + " chunk at byte " + std::to_string(at) + " runs past the end of the file";
    const std::uint32_t expected = png_be32(stored);
    if ((crc ^ 0xffffffffu) != expected)
      return "the " + type + " chunk at byte " + std::to_string(at) + " fails its checksum";
    if (type == "IHDR" && length != 13) return "its IHDR chunk holds " + std::to_string(length) + " bytes, not 13";
    // libpng's fatal "out of place"; its rows were laid out by the first.
    if (type == "IHDR" && chunks > 0) return "it holds a second IHDR chunk at byte " + std::to_string(at);
    if (!header.empty()) return header;
    if (!inflated.empty()) return inflated;
    const std::string where = " at byte " + std::to_string(at);
    if (type == "PLTE") {
      if (palette_seen) return "it holds a second PLTE chunk" + where;
      if (length == 0 || length % 3 != 0 || length > 3 * 256)
        return "its PLTE chunk" + where + " holds " + std::to_string(length) + " bytes, not 1 to 256 colours of 3";
      palette_seen = true;
    }
    if (type == "IDAT" && colour_type == 3 && !palette_seen)
      return "it is a palette picture without its palette: no PLTE chunk before its image data" + where;
    if (type == "IDAT") {
      idat_seen = true;
    } else if (idat_seen && !idat_over) {
      idat_over = true;
      if (const std::string why = rows ? rows->end() : ""; !why.empty()) return why;
    }
    if (type == "IEND") return rows ? rows->end() : "";
    at += 12 + std::uint64_t{length};
  }
}

}  // namespace caustic::design
