// SPDX-License-Identifier: LGPL-2.1-or-later
// A JPEG file's marker segments, walked as libjpeg's marker reader walks
// them, for the checks that read a picture before any decoder sees it (its
// size, its count of scans). One walk for all of them: a check that walked
// differently from the decoder (stopping at a stray byte the decoder
// skips) once missed every scan behind that byte.
#pragma once

#include <cstddef>
#include <optional>

namespace caustic {

class JpegMarkers {
 public:
  struct Segment {
    unsigned char marker;  ///< the byte after 0xFF: 0xC0 (SOF0), 0xDA (SOS), 0xD9 (EOI) ...
    std::size_t at;        ///< offset of its 0xFF
    std::size_t length;    ///< its length field (2 and up), 0 for a marker that has none (RSTn, SOI, EOI, TEM)
  };

  /// A walk of `data` (a JPEG file's bytes, not copied); it yields nothing
  /// unless the data starts with SOI (FF D8).
  JpegMarkers(const unsigned char* data, std::size_t size);

  /// The next marker: bytes between segments that are no marker are
  /// skipped (libjpeg warns and skips them too), fill bytes (FF FF) as
  /// well, and after an SOS its entropy-coded data (where 0xFF is stuffed
  /// with 0x00 and restart markers stand alone). Nothing at the end of the
  /// data, or at a length field cut off or below 2; a segment whose length
  /// runs past the end is yielded, and ends the walk.
  std::optional<Segment> next();

 private:
  const unsigned char* data_;
  std::size_t size_, pos_ = 2;
  bool in_scan_ = false;  // the last segment was an SOS: its coded data follows
};

}  // namespace caustic
