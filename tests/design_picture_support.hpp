// SPDX-License-Identifier: LGPL-2.1-or-later
// What the designer's picture tests share: a scratch folder, a picture's
// refusal in words, and a PNG as the image library writes it.
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

// A 256 x 256 PNG of varied colour, as the image library writes it.
inline std::string png_bytes(const Folder& folder) {
  const auto file = folder.path / "written.png";
  std::vector<unsigned char> pixels(256 * 256 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>((i * 7919) % 251);
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out || !out->open(file.string(), OIIO::ImageSpec(256, 256, 3, OIIO::TypeDesc::UINT8)) ||
      !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
    return "";
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace caustic::testing::design_picture
