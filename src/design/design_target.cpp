// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/design_target.hpp"

#include "caustic/jpeg_scans.hpp"
#include "png_chunks.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace caustic::design {
namespace {

// The sRGB decoding curve (IEC 61966-2-1), input and output in [0, 1].
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

bool is_float_format(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::HALF ||
         t.basetype == OIIO::TypeDesc::DOUBLE;
}

// Integer pictures are display-referred (sRGB) unless their metadata says
// linear; float pictures are scene-referred (linear) unless it says sRGB.
bool encoded_srgb(const OIIO::ImageSpec& spec) {
  std::string cs = spec.get_string_attribute("oiio:ColorSpace");
  std::transform(cs.begin(), cs.end(), cs.begin(), [](unsigned char c) { return std::tolower(c); });
  if (cs.find("linear") != std::string::npos) return false;
  if (cs.find("srgb") != std::string::npos) return true;
  return !is_float_format(spec.format);
}

// Exact overlap weights of n output cells over `in` input samples along one axis.
struct Span {
  int first = 0;
  std::vector<double> weights;
};
std::vector<Span> box_spans(int offset, int in, int n) {
  std::vector<Span> spans(n);
  const double scale = static_cast<double>(in) / n;
  for (int o = 0; o < n; ++o) {
    const double a = o * scale, b = (o + 1) * scale;
    Span& s = spans[o];
    s.first = offset + static_cast<int>(std::floor(a));
    for (int p = static_cast<int>(std::floor(a)); p < in && p < b; ++p) {
      const double w = std::min(b, p + 1.0) - std::max(a, static_cast<double>(p));
      s.weights.push_back(std::max(w, 0.0) / scale);
    }
  }
  return spans;
}

std::string size_error(const std::string& name, long long width, long long height) {
  return name + ": " + std::to_string(width) + "x" + std::to_string(height) + " pixels is too large (at most " +
         std::to_string(kMaxTargetSide) + " per side and " + std::to_string(kMaxTargetPixels) + " in all)";
}

bool too_large(long long width, long long height) {
  return width > kMaxTargetSide || height > kMaxTargetSide || width * height > kMaxTargetPixels;
}

// A GIF's screen size, read before its reader sees the file: that reader
// makes the whole canvas on open, before the size below can be checked (a
// 13-byte file claiming 65535 x 65535 threw out of it; 40000 x 40000 took
// 2 GiB before it gave up).
void check_gif_screen(const std::filesystem::path& file, const std::string& name) {
  unsigned char head[10] = {};
  std::ifstream in(file, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return;
  if (std::memcmp(head, "GIF87a", 6) != 0 && std::memcmp(head, "GIF89a", 6) != 0) return;
  const long long width = head[6] | head[7] << 8, height = head[8] | head[9] << 8;
  if (too_large(width, height)) throw TargetError(size_error(name, width, height));
}

// A GIF's images, counted by walking its blocks up to `bound` + 1: its
// reader would decode every frame onto the whole canvas to seek the last.
int gif_images(const std::filesystem::path& file, int bound) {
  std::ifstream in(file, std::ios::binary);
  unsigned char head[13] = {};
  if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return 1;
  const auto table = [](unsigned char flags) { return flags & 0x80 ? 3 << ((flags & 7) + 1) : 0; };
  in.ignore(table(head[10]));
  const auto skip_blocks = [&] {  // sub-blocks, each its length first, a 0 last
    for (int n = in.get(); n > 0; n = in.get()) in.ignore(n);
  };
  int images = 0;
  for (int block = in.get(); in && block != 0x3b; block = in.get()) {
    if (block == 0x21) {  // an extension: its label, then its sub-blocks
      in.get();
      skip_blocks();
    } else if (block == 0x2c) {  // an image: its descriptor, colour table, code size, data
      unsigned char d[9] = {};
      if (!in.read(reinterpret_cast<char*>(d), sizeof d)) break;
      in.ignore(table(d[8]) + 1);
      skip_blocks();
      if (++images > bound) break;
    } else {
      break;
    }
  }
  return std::max(images, 1);
}

// How many images the file holds (pages, frames, parts), counted to
// `bound` + 1 (more than `bound`); only the first is read. A Photoshop file's first is its composite, the
// picture as shown, and its layers follow: it is one picture.
int images_held(OIIO::ImageInput& in, const std::filesystem::path& file, int bound) {
  const std::string format = in.format_name();
  if (format == "psd") return 1;
  if (format == "gif") return gif_images(file, bound);
  int n = 1;
  while (n <= bound && in.seek_subimage(n, 0)) ++n;
  in.geterror();  // a failed seek is no damage
  return n;
}

// A JPEG's scans, counted before its decoder sees it (caustic/jpeg_scans.hpp:
// each scan redoes the decoder's work, and 140,000 held a core for 40 min).
void check_jpeg_scans(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  // Read whole only when it is a JPEG: any other picture is up to
  // kMaxTargetFileBytes its reader reads again.
  if (in.get() != 0xff || in.get() != 0xd8) return;
  in.seekg(0);
  std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (jpeg_scans(bytes.data(), bytes.size()) > kMaxJpegScans)
    throw TargetError(name + ": the JPEG holds more than " + std::to_string(kMaxJpegScans) + " scans");
}

// A PNG's chunks, checked before libpng reads it (png_chunks.hpp): libpng
// said its error on stderr itself, beside the message. Gives an animated
// PNG's frame count (its reader reads the still image alone), else 1.
std::uint32_t check_png_chunks(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  std::uint32_t frames = 1;
  // Rows of the largest picture designed (16-bit RGBA), and a filter byte a
  // row: Adam7's passes hold at most 15/8 rows a row, and 7 more. A header
  // beyond it is refused by its size below, its data not inflated.
  constexpr std::uint64_t rows = static_cast<std::uint64_t>(kMaxTargetPixels) * 8 + 2 * kMaxTargetSide;
  if (const std::string why = png_damage(in, &frames, rows); !why.empty())
    throw TargetError(name + ": the picture is damaged or cut short (" + why + "); save it again");
  // Its size, from the IHDR found whole above, before libpng: a side over
  // its limit (a million) was its "Invalid IHDR data", on stderr as well.
  unsigned char head[24] = {};
  in.clear();
  in.seekg(0);
  if (in.read(reinterpret_cast<char*>(head), sizeof head) && std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0 &&
      std::memcmp(head + 12, "IHDR", 4) == 0) {
    if (too_large(png_be32(head + 16), png_be32(head + 20)))
      throw TargetError(size_error(name, png_be32(head + 16), png_be32(head + 20)));
  }
  return frames;
}

// The picture as it is meant to be seen: a camera that was held on its side
// stores its rows as the sensor read them and says in EXIF's Orientation
// (1-8) how to turn them; a phone's portrait was designed lying down.
bool turned_sides(int orientation) { return orientation >= 5 && orientation <= 8; }  // 5-8 swap the sides

// Where the stored pixel (sx, sy) of a w x h picture is shown upright,
// rows from the top.
void upright_pixel(int orientation, int w, int h, int sx, int sy, int& x, int& y) {
  x = sx, y = sy;
  switch (orientation) {
    case 2: x = w - 1 - sx; break;                      // mirrored
    case 3: x = w - 1 - sx, y = h - 1 - sy; break;      // upside down
    case 4: y = h - 1 - sy; break;                      // mirrored upside down
    case 5: x = sy, y = sx; break;                      // transposed
    case 6: x = h - 1 - sy, y = sx; break;              // to be turned a quarter clockwise
    case 7: x = h - 1 - sy, y = w - 1 - sx; break;      // transversed
    case 8: x = sy, y = w - 1 - sx; break;              // to be turned a quarter anticlockwise
    default: break;                                     // 1, or a value EXIF does not define: as stored
  }
}

// What a reader says, on one line: libtiff's (and libpng's) errors may be
// several lines, which a message (and a problem+json detail) would carry
// as they are.
std::string reader_words(std::string said) {
  while (!said.empty() && (said.back() == '\n' || said.back() == ' ')) said.pop_back();
  for (std::size_t at = said.find('\n'); at != std::string::npos; at = said.find('\n', at))
    said.replace(at, 1, "; ");
  return said;
}

// Opened once by hand, so that a file the process may not read is said so
// (the image library tries every format's reader and reports that none
// could read it).
void check_opens(const std::filesystem::path& file, const std::string& name) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw TargetError(name + ": cannot open the picture (" + std::strerror(errno) + ")");
  ::close(fd);
}

// The picture's reader, open; `first` is the spec it gave when opened
// before: a file changed between the two readings is refused.
std::unique_ptr<OIIO::ImageInput> open_picture(const std::string& name, const OIIO::ImageSpec* first = nullptr) {
  std::unique_ptr<OIIO::ImageInput> in;
  try {
    in = OIIO::ImageInput::open(name);
  } catch (const std::exception& e) {  // a reader that throws (allocation, length) rather than failing
    throw TargetError(name + ": cannot read the picture (" + reader_words(e.what()) + ")");
  }
  if (!in) throw TargetError(name + ": cannot read the picture (" + reader_words(OIIO::geterror()) + ")");
  const OIIO::ImageSpec& spec = in->spec();
  if (first && (spec.width != first->width || spec.height != first->height || spec.nchannels != first->nchannels ||
                spec.tile_width != first->tile_width || spec.tile_height != first->tile_height))
    throw TargetError(name + ": the picture changed while it was read");
  return in;
}

// Decodes the picture a band of rows at a time (`channels` floats a pixel),
// handing each band to `take` with its first and last row: the decoder's
// floats of the whole picture never lie beside the picture kept. A tiled
// file's bands are whole rows of tiles, so each tile is decoded once.
void read_bands(OIIO::ImageInput& in, const std::string& name, int channels,
                const std::function<void(int y0, int y1, const float* rows)>& take) {
  const OIIO::ImageSpec& spec = in.spec();
  const int w = spec.width, h = spec.height;
  const bool tiled = spec.tile_width > 0 && spec.tile_height > 0;
  int band = std::clamp(static_cast<int>((1 << 20) / (std::int64_t{w} * channels)), 1, h);
  if (tiled) band = std::min(h, std::max(1, band / spec.tile_height) * spec.tile_height);
  std::vector<float> raw;
  for (int y0 = 0; y0 < h; y0 += band) {
    const int y1 = std::min(h, y0 + band);
    bool read = false;
    try {
      raw.resize(static_cast<std::size_t>(w) * (y1 - y0) * channels);
      read = tiled ? in.read_tiles(0, 0, spec.x, spec.x + w, spec.y + y0, spec.y + y1, spec.z, spec.z + 1, 0, channels,
                                   OIIO::TypeDesc::FLOAT, raw.data())
                   : in.read_scanlines(0, 0, spec.y + y0, spec.y + y1, spec.z, 0, channels, OIIO::TypeDesc::FLOAT,
                                       raw.data());
    } catch (const std::exception& e) {
      throw TargetError(name + ": cannot decode the picture (" + reader_words(e.what()) + ")");
    }
    // Read once: the reader forgets its error as it gives it (a message
    // once said "cut short ()").
    const std::string said = reader_words(in.geterror());
    if (!read) throw TargetError(name + ": cannot decode the picture (" + said + ")");
    // A reader that reads on past damage: libtiff's strips cut short were
    // rows of black, and a JPEG cut short decodes its missing rows grey,
    // with only a warning (libjpeg's "premature end"); designed, they drew
    // a band the report could not see, since it judges against the decoded
    // picture. libjpeg tells only its first warning, so any corrupt data is
    // refused: a stray byte's warning once hid the truncation behind it.
    if (!said.empty()) throw TargetError(name + ": the picture is damaged or cut short (" + said + "); save it again");
    take(y0, y1, raw.data());
  }
}

}  // namespace

RgbHdrImage load_target_rgb(const std::filesystem::path& file, std::vector<std::string>* warnings) {
  const std::string name = file.string();
  // A regular file of bounded size: a device or a pipe would be read, and
  // probed by every format's reader, without end.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw TargetError(name + ": is not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (bytes > kMaxTargetFileBytes || ec)
    throw TargetError(name + ": is larger than " + std::to_string(kMaxTargetFileBytes >> 20) + " MiB");
  // A kernel file (/proc/kmsg) says it holds nothing and then waits for
  // what it may never hold; an empty picture file has nothing to read.
  if (bytes == 0) throw TargetError(name + ": is empty");
  check_opens(file, name);
  check_gif_screen(file, name);
  check_jpeg_scans(file, name);
  const std::uint32_t png_frames = check_png_chunks(file, name);
  std::unique_ptr<OIIO::ImageInput> in = open_picture(name);
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw TargetError(name + ": the picture is empty");
  // A volume's slices would all be read into a buffer sized for one.
  if (spec.depth > 1) throw TargetError(name + ": is a volume of " + std::to_string(spec.depth) + " slices, not a picture");
  if (too_large(spec.width, spec.height)) throw TargetError(size_error(name, spec.width, spec.height));
  // A tile is decoded whole, in floats, wherever the picture ends: a 35 KB
  // TIFF of 256 x 256 pixels in tiles of 32752 a side held 16 GB for 40 s
  // before its decoder gave up. A tile may be as large as the picture (a
  // TIFF's sides round up to 16), within the picture's own bound, or
  // kMaxTargetTile a side.
  const auto tile_fits = [](int tile, int side) { return tile <= std::max(kMaxTargetTile, side + 15); };
  if (spec.tile_width > 0 &&
      (!tile_fits(spec.tile_width, spec.width) || !tile_fits(spec.tile_height, spec.height) || spec.tile_depth > 1))
    throw TargetError(name + ": its tiles of " + std::to_string(spec.tile_width) + "x" + std::to_string(spec.tile_height) +
                      " pixels are larger than the picture and than " + std::to_string(kMaxTargetTile) +
                      " a side (each is decoded whole); save it untiled or in smaller tiles");
  if (std::min(spec.width, spec.height) < kMinTargetSide)
    throw TargetError(name + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                      " pixels is too thin (at least " + std::to_string(kMinTargetSide) +
                      " a side: the design takes its centre square)");
  // R, G, B and alpha at the most: what lies beyond is never used, and a
  // file of a few kilobytes may declare hundreds of channels.
  const int channels = std::min(spec.nchannels, 4);
  // Decoded once to no purpose but to show the pixels are there: a header
  // of a few bytes may declare 64 M pixels, whose picture (12 bytes a pixel,
  // 768 MB) was set aside before the reader found no data behind it.
  read_bands(*in, name, channels, [](int, int, const float*) {});
  // A multi-page TIFF or an animated GIF or PNG looks like one picture to
  // whoever chose it (a viewer shows its first page, a browser plays the
  // frames).
  const auto held = [&] {
    return png_frames > 1 ? static_cast<int>(std::min<std::uint32_t>(png_frames, 101)) : images_held(*in, file, 100);
  };
  if (const int images = warnings ? held() : 1; images > 1)
    warnings->push_back(name + ": holds " + (images > 100 ? "more than 100" : std::to_string(images)) +
                        " images (pages, frames or parts); only the first is designed");
  in = open_picture(name, &spec);
  const bool srgb = encoded_srgb(spec);
  // Colour: the first three channels are R, G, B; grey (1 or 2 channels): the first.
  const bool colour = channels >= 3;
  // Converted and turned upright band by band into the one full-size
  // picture kept: a turned copy once lay beside it.
  const int orientation = spec.get_int_attribute("Orientation", 1);
  const int w = spec.width, h = spec.height;
  const bool turned = turned_sides(orientation);
  RgbHdrImage out{turned ? h : w, turned ? w : h, {}};
  try {
    out.pixels.resize(3 * static_cast<std::size_t>(w) * h);
  } catch (const std::bad_alloc&) {
    throw TargetError(name + ": " + std::to_string(w) + "x" + std::to_string(h) + " pixels do not fit in memory");
  }
  // Transparent pixels are black as read (the reader multiplies colour by
  // alpha): a dark logo on a transparent ground, black all over as
  // designed, is told why rather than only "all black".
  const int alpha = spec.channelindex("A") < channels ? spec.channelindex("A") : -1;
  std::size_t transparent = 0;
  bool lit = false;
  read_bands(*in, name, channels, [&](int y0, int y1, const float* raw) {
    for (int sy = y0; sy < y1; ++sy)
      for (int sx = 0; sx < w; ++sx) {
        const float* c = &raw[(static_cast<std::size_t>(sy - y0) * w + sx) * channels];
        transparent += alpha >= 0 && c[alpha] < 1;
        const double rgb[3] = {c[0], colour ? c[1] : c[0], colour ? c[2] : c[0]};
        int x = 0, y = 0;
        upright_pixel(orientation, w, h, sx, sy, x, y);
        float* to = &out.pixels[3 * (static_cast<std::size_t>(y) * out.width + x)];
        for (int k = 0; k < 3; ++k) {
          double v = rgb[k];
          if (!std::isfinite(v)) throw TargetError(name + ": the picture holds NaN or infinite values");
          v = std::max(v, 0.0);
          if (srgb) v = srgb_to_linear(std::min(v, 1.0));
          to[k] = static_cast<float>(v);
          lit = lit || v > 0;
        }
      }
  });
  if (!lit && transparent > 0)
    throw TargetError(name + ": is all black: its " + std::to_string(transparent) +
                      " transparent pixels are taken as black (no light) and the others are black; lay it over a "
                      "light background to design it as a viewer shows it on one");
  return out;
}

Image load_target(const std::filesystem::path& file, std::vector<std::string>* warnings) {
  return luminance(load_target_rgb(file, warnings));
}

Image box_resample_square(const Image& image, int n) {
  const int side = std::min(image.width, image.height);
  const auto xs = box_spans((image.width - side) / 2, side, n);
  const auto ys = box_spans((image.height - side) / 2, side, n);
  // Separable: rows first into a side x n buffer, then columns.
  std::vector<double> rows(static_cast<std::size_t>(image.height) * n, 0.0);
  for (int y = 0; y < image.height; ++y)
    for (int o = 0; o < n; ++o) {
      double s = 0;
      for (std::size_t k = 0; k < xs[o].weights.size(); ++k) s += xs[o].weights[k] * image.at(xs[o].first + k, y);
      rows[static_cast<std::size_t>(y) * n + o] = s;
    }
  Image out{n, n, std::vector<float>(static_cast<std::size_t>(n) * n)};
  for (int o = 0; o < n; ++o)
    for (int x = 0; x < n; ++x) {
      double s = 0;
      for (std::size_t k = 0; k < ys[o].weights.size(); ++k)
        s += ys[o].weights[k] * rows[static_cast<std::size_t>(ys[o].first + k) * n + x];
      out.pixels[static_cast<std::size_t>(o) * n + x] = static_cast<float>(s);
    }
  return out;
}

}  // namespace caustic::design
