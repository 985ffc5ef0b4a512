// SPDX-License-Identifier: LGPL-2.1-or-later
// Writing and reading renders: EXR for HDR relative irradiance, PNG for the
// tone-mapped picture (OpenImageIO).
#pragma once

#include "caustic/image.hpp"

#include <filesystem>
#include <stdexcept>
#include <vector>

namespace caustic {

class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One float channel "Y" (relative irradiance), 32-bit float EXR.
void write_exr(const HdrImage& image, const std::filesystem::path& file);
/// Channels "R", "G", "B" (linear sRGB relative irradiance, a spectral
/// frame), 32-bit float EXR.
void write_exr(const RgbHdrImage& image, const std::filesystem::path& file);
/// 8-bit RGB PNG (alpha dropped).
void write_png(const Rgba8Image& image, const std::filesystem::path& file);
/// The picture as PNG file bytes, for serving without touching the disk.
std::vector<unsigned char> encode_png(const Rgba8Image& image);
/// The HDR image as EXR file bytes (one float channel "Y", as write_exr).
std::vector<unsigned char> encode_exr(const HdrImage& image);
/// The same for a colour image (channels "R", "G", "B", as write_exr).
std::vector<unsigned char> encode_exr(const RgbHdrImage& image);
/// Reads the first channel of any image OpenImageIO can open, as float.
HdrImage read_hdr_image(const std::filesystem::path& file);
/// Reads R, G, B as float; an image with fewer than three channels reads
/// as grey (its first channel in all three).
RgbHdrImage read_rgb_image(const std::filesystem::path& file);

}  // namespace caustic
