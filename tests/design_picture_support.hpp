// SPDX-License-Identifier: LGPL-2.1-or-later
// What the designer's picture tests share: a scratch folder, a picture's
// refusal in words, and a picture as the image library writes it.
#pragma once

#include "caustic/design_target.hpp"
#include "refusal.hpp"

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace caustic::testing::design_picture {

struct Folder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("causticd_design_picture_" + std::to_string(::getpid()));
  Folder() { std::filesystem::create_directories(path); }
  ~Folder() { std::filesystem::remove_all(path); }
  std::filesystem::path write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path / name, std::ios::binary) << bytes;
    return path / name;
  }
};

inline std::string refused(const std::filesystem::path& file) {
  return caustic::testing::refusal<caustic::design::TargetError>([&] { caustic::design::load_target_rgb(file); });
}

// A `w` x `h` picture of varied colour as the image library writes it to
// `name` in the folder (the format by its extension; in tiles of `tile`
// x `tile_height` pixels when `tile` > 0), its bytes; "" if it could not.
inline std::string written_bytes(const Folder& folder, const std::string& name, int w, int h, int tile = 0,
                                 int tile_height = 0) {
  const auto file = folder.path / name;
  std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>((i * 7919) % 251);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  spec.tile_width = tile, spec.tile_height = tile_height;
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
    return "";
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 256 x 256 PNG of varied colour, as the image library writes it.
inline std::string png_bytes(const Folder& folder) { return written_bytes(folder, "written.png", 256, 256); }

}  // namespace caustic::testing::design_picture
