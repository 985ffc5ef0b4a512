// SPDX-License-Identifier: LGPL-2.1-or-later
// Target pictures for the designer: reading any image OpenImageIO opens as
// linear luminance, and box resampling onto the design grid.
#pragma once

#include <cstdint>

#include "caustic/engine.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustic::design {

/// A rejected target picture; the message names the file.
class TargetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Linear luminance, row 0 at the top.
using Image = HdrImage;

/// Largest picture accepted, per side and in pixels: a bound on memory, far
/// above any useful design resolution.
inline constexpr int kMaxTargetSide = 16384;
inline constexpr long long kMaxTargetPixels = 1LL << 26;
/// Largest tile side accepted beyond the picture's own size: a tile is
/// decoded whole wherever the picture ends, and writers tile at 64 to 512.
inline constexpr int kMaxTargetTile = 4096;
/// Smallest side accepted: the design takes the picture's centre square,
/// and a picture a pixel wide left one pixel of it (refused as black).
inline constexpr int kMinTargetSide = 2;
/// The largest picture file read: a picture's reader probes a file it does
/// not know by trying every format over the whole of it.
inline constexpr std::uintmax_t kMaxTargetFileBytes = std::uintmax_t{256} << 20;

/// Reads `file` (PNG, JPEG, EXR, TIFF, ...) as linear luminance
/// Y = 0.2126 R + 0.7152 G + 0.0722 B. Integer formats are taken as sRGB
/// (the curve is undone) unless the file says it is linear; float formats as
/// linear. Grey files use their one channel. Colour is as the picture shows
/// laid over black (the reader multiplies it by alpha): a transparent pixel
/// is black, and receives no light. Throws
/// TargetError for an unreadable, damaged, empty, oversized or non-finite
/// picture. What a user may not expect of a picture read (a file of several
/// images, of which the first is read) is added to `warnings`, each naming
/// the file.
Image load_target(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr);

/// The same picture in linear RGB (grey files: R = G = B), for colour
/// designs (design_colour.hpp).
RgbHdrImage load_target_rgb(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr);

/// Centre square crop of `image`, then a box filter onto n x n cells: every
/// cell is the exact area-weighted mean of the pixels it covers, so a picture
/// already n x n comes back unchanged.
Image box_resample_square(const Image& image, int n);

}  // namespace caustic::design
