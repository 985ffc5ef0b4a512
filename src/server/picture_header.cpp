// SPDX-License-Identifier: LGPL-2.1-or-later
#include "picture_header.hpp"

#include "caustic/jpeg_markers.hpp"

#include <algorithm>
#include <cstring>

namespace caustic::server {
namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}
std::uint32_t be16(const unsigned char* p) { return (std::uint32_t(p[0]) << 8) | p[1]; }

}  // namespace

PictureHeader read_picture_header(const unsigned char* data, std::size_t size) {
  PictureHeader out;
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 8 && std::memcmp(data, png, 8) == 0) {
    out.format = PictureHeader::Format::png;
    // The first chunk must be IHDR, 13 bytes long (PNG spec 11.2.2).
    if (size >= 24 && be32(data + 8) == 13 && std::memcmp(data + 12, "IHDR", 4) == 0) {
      out.width = be32(data + 16);
      out.height = be32(data + 20);
      // Zero and sizes beyond 2^31 - 1 are invalid PNG.
      if (!out.width || !out.height || out.width > 0x7fffffffu || out.height > 0x7fffffffu) out.width = out.height = 0;
    }
    return out;
  }
  if (size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff) {
    out.format = PictureHeader::Format::jpeg;
    caustic::JpegMarkers markers(data, size);
    while (const auto segment = markers.next()) {
      const unsigned char marker = segment->marker;
      if (marker == 0xd9 || marker == 0xda) return out;  // end, or scan data before any frame header
      // SOF0..SOF15 without DHT (C4), JPG (C8) and DAC (CC): P, Y, X follow the length.
      const bool sof = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
      if (!sof) continue;
      const std::size_t pos = segment->at;
      if (pos + 9 > size || segment->length < 7) return out;
      out.height = be16(data + pos + 5);
      out.width = be16(data + pos + 7);
      // A height of 0 defers it to a DNL marker after the scan: not taken.
      if (!out.height || !out.width) out.width = out.height = 0;
      return out;
    }
    return out;
  }
  return out;
}

bool picture_complete(const unsigned char* data, std::size_t size, PictureHeader::Format format) {
  if (format == PictureHeader::Format::png) {
    // ... IEND, then its 4-byte CRC: the type sits 8 bytes from the end.
    static const unsigned char kIend[] = {'I', 'E', 'N', 'D'};
    return size >= 12 && std::equal(kIend, kIend + 4, data + size - 8);
  }
  if (format == PictureHeader::Format::jpeg) {
    // Entropy-coded data stuffs every 0xFF with 0x00: FF D9 is the marker.
    for (std::size_t i = size >= 4096 ? size - 4096 : 0; i + 1 < size; ++i)
      if (data[i] == 0xFF && data[i + 1] == 0xD9) return true;
    return false;
  }
  return false;
}

const char* media_type(PictureHeader::Format format) {
  switch (format) {
    case PictureHeader::Format::png: return "image/png";
    case PictureHeader::Format::jpeg: return "image/jpeg";
    default: return "";
  }
}

const char* extension(PictureHeader::Format format) {
  switch (format) {
    case PictureHeader::Format::png: return ".png";
    case PictureHeader::Format::jpeg: return ".jpg";
    default: return "";
  }
}

}  // namespace caustic::server
