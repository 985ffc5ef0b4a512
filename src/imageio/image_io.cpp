#include "caustic/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

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

void write_png(const Rgba8Image& image, const std::filesystem::path& file) {
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  write(file, spec, image.pixels.data(), OIIO::TypeDesc::UINT8, 4);
}

std::vector<unsigned char> encode_png(const Rgba8Image& image) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw ImageIoError("no PNG writer: " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  void* proxy = &memory;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  if (!out->open("thumbnail.png", spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data(), 4) ||
      !out->close())
    throw ImageIoError("cannot encode PNG: " + out->geterror());
  return bytes;
}

HdrImage read_hdr_image(const std::filesystem::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) throw ImageIoError("cannot read " + file.string() + ": " + OIIO::geterror());
  const auto& spec = in->spec();
  HdrImage img{spec.width, spec.height, std::vector<float>(static_cast<std::size_t>(spec.width) * spec.height)};
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw ImageIoError("cannot read " + file.string() + ": " + in->geterror());
  return img;
}

}  // namespace caustic
