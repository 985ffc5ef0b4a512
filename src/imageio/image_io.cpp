// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

namespace caustic {
namespace {

void write(const std::filesystem::path& file, const OIIO::ImageSpec& spec, const void* pixels, OIIO::TypeDesc type,
           OIIO::stride_t xstride) {
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out) throw ImageIoError("cannot write " + file.string() + ": " + OIIO::geterror());
  if (!out->open(file.string(), spec) || !out->write_image(type, pixels, xstride) || !out->close())
    throw ImageIoError("cannot write " + file.string() + ": " + out->geterror());
}

}  // namespace

void write_exr(const HdrImage& image, const std::filesystem::path& file) {
  OIIO::ImageSpec spec(image.width, image.height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Y"};
  spec.attribute("compression", "zip");
  write(file, spec, image.pixels.data(), OIIO::TypeDesc::FLOAT, OIIO::AutoStride);
}

void write_exr(const RgbHdrImage& image, const std::filesystem::path& file) {
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B"};
  spec.attribute("compression", "zip");
  write(file, spec, image.pixels.data(), OIIO::TypeDesc::FLOAT, OIIO::AutoStride);
}

void write_png(const Rgba8Image& image, const std::filesystem::path& file) {
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  write(file, spec, image.pixels.data(), OIIO::TypeDesc::UINT8, 4);
}

namespace {

// Writes through OpenImageIO's memory proxy: the same writers as the files,
// without touching the disk.
std::vector<unsigned char> encode(const char* format, const OIIO::ImageSpec& given, const void* pixels,
                                  OIIO::TypeDesc type, OIIO::stride_t xstride) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create(format);
  if (!out) throw ImageIoError(std::string("no ") + format + " writer: " + OIIO::geterror());
  OIIO::ImageSpec spec = given;
  void* proxy = &memory;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  if (!out->open(std::string("picture.") + format, spec) || !out->write_image(type, pixels, xstride) || !out->close())
    throw ImageIoError(std::string("cannot encode ") + format + ": " + out->geterror());
  return bytes;
}

}  // namespace

std::vector<unsigned char> encode_png(const Rgba8Image& image) {
  return encode("png", OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::UINT8), image.pixels.data(),
                OIIO::TypeDesc::UINT8, 4);
}

std::vector<unsigned char> encode_exr(const HdrImage& image) {
  OIIO::ImageSpec spec(image.width, image.height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Y"};
  return encode("exr", spec, image.pixels.data(), OIIO::TypeDesc::FLOAT, OIIO::AutoStride);
}

std::vector<unsigned char> encode_exr(const RgbHdrImage& image) {
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B"};
  return encode("exr", spec, image.pixels.data(), OIIO::TypeDesc::FLOAT, OIIO::AutoStride);
}

namespace {

// A picture OpenImageIO opened, refused unless it is one flat picture: a
// volume's slices would all be read into a buffer sized for one.
std::unique_ptr<OIIO::ImageInput> open_picture(const std::filesystem::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) throw ImageIoError("cannot read " + file.string() + ": " + OIIO::geterror());
  const auto& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
    throw ImageIoError("cannot read " + file.string() + ": not one flat picture (" + std::to_string(spec.width) + "x" +
                       std::to_string(spec.height) + "x" + std::to_string(spec.depth) + ", " +
                       std::to_string(spec.nchannels) + " channels)");
  return in;
}

}  // namespace

HdrImage read_hdr_image(const std::filesystem::path& file) {
  auto in = open_picture(file);
  const auto& spec = in->spec();
  HdrImage img{spec.width, spec.height, std::vector<float>(static_cast<std::size_t>(spec.width) * spec.height)};
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw ImageIoError("cannot read " + file.string() + ": " + in->geterror());
  return img;
}

RgbHdrImage read_rgb_image(const std::filesystem::path& file) {
  auto in = open_picture(file);
  const auto& spec = in->spec();
  const std::size_t n = static_cast<std::size_t>(spec.width) * spec.height;
  RgbHdrImage img{spec.width, spec.height, std::vector<float>(3 * n)};
  const int channels = std::min(spec.nchannels, 3);
  std::vector<float> raw(n * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data()))
    throw ImageIoError("cannot read " + file.string() + ": " + in->geterror());
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) img.pixels[3 * i + c] = raw[i * channels + (channels == 3 ? c : 0)];
  return img;
}

}  // namespace caustic
