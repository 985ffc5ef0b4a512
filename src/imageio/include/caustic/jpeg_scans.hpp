// SPDX-License-Identifier: LGPL-2.1-or-later
// How many scans a JPEG holds, read from its markers before any decoder
// sees it. A progressive JPEG refines its picture scan by scan, and the
// decoder redoes its work for each: a 4096² picture followed by its last
// scan repeated 140,000 times (8 MB) held a core for about 40 minutes,
// with nothing to stop it. Pictures a camera or an editor writes have 1
// (baseline) to about 12 scans.
#pragma once

#include <cstddef>

namespace caustic {

/// At most this many scans are decoded.
inline constexpr std::size_t kMaxJpegScans = 64;

/// The start-of-scan (SOS) markers in `data` (a JPEG file's bytes), counted
/// through the marker segments and past each scan's entropy-coded data
/// (where 0xFF is stuffed with 0x00, and restart markers stand alone).
/// Bytes between segments that are no marker are skipped, as libjpeg skips
/// them (one stray byte once hid every scan behind it from the count).
/// Counting stops past `limit` (a hostile file need not be walked whole),
/// at EOI and at the end of the data.
std::size_t jpeg_scans(const unsigned char* data, std::size_t size, std::size_t limit = kMaxJpegScans);

}  // namespace caustic
