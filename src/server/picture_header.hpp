// SPDX-License-Identifier: LGPL-2.1-or-later
// The format and size of an uploaded picture, read from its first bytes
// before anything decodes it: a format outside the short list, or a header
// that claims more pixels than the server takes, is refused on the request
// thread without handing the bytes to an image library. Pure; tested and
// fuzzed on its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace caustic::server {

struct PictureHeader {
  enum class Format { unknown, png, jpeg };
  Format format = Format::unknown;
  std::uint32_t width = 0, height = 0;  ///< 0 when the header holds none (cut short, broken)
};

/// Sniffs PNG (signature, then IHDR first) or baseline/progressive JPEG
/// (SOI, then markers up to the first SOFn, walked as the decoder walks
/// them: caustic/jpeg_markers.hpp).
PictureHeader read_picture_header(const unsigned char* data, std::size_t size);

/// Whether the bytes run to the format's end: a PNG's last chunk is IEND, a
/// JPEG's end-of-image marker lies in its last 4 KiB (trailing bytes after
/// it are common). A picture cut short has a whole header and fails only
/// when decoded; this sees it on the request thread, without decoding.
bool picture_complete(const unsigned char* data, std::size_t size, PictureHeader::Format format);

/// The media type of a format ("image/png"), and its file extension (".png").
const char* media_type(PictureHeader::Format format);
const char* extension(PictureHeader::Format format);

}  // namespace caustic::server
