// SPDX-License-Identifier: LGPL-2.1-or-later
// Draws the target pictures of the built-in designed scenes that the build
// makes itself (no binary picture is committed): a logo (ring, star and bar)
// and lines of text set in a TrueType font. Both are white on black, square,
// 8-bit greyscale PNG, which `causticd design` reads as sRGB.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// The logo of bench/design_targets.py: a thin ring, a five-pointed star cut
// flat at the bottom and a bar under it, in [-1, 1]^2 with y up. Thin lines,
// sharp points and a large black area are what a caustic finds hardest.
bool inside_logo(double x, double y) {
  const double r = std::hypot(x, y);
  if (r > 0.78 && r < 0.9) return true;
  const double pi = std::numbers::pi, sector = 2 * pi / 5;
  const double a = std::atan2(y, x) + pi / 2;
  const double k = std::fmod(a + 2 * pi, sector) - sector / 2;
  const double star = 0.3 + 0.32 * std::pow(1 - std::abs(k) / (sector / 2), 2);
  if (r < star && y > -0.45) return true;
  return std::abs(x) < 0.5 && y > -0.68 && y < -0.56;
}

// Coverage by 4x4 supersampling, so edges are anti-aliased rather than stairs.
ImageBuf logo(int n) {
  ImageBuf img(ImageSpec(n, n, 1, TypeDesc::FLOAT));
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      int hits = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx)
          hits += inside_logo((col + (sx + 0.5) / 4) / n * 2 - 1, 1 - (row + (sy + 0.5) / 4) / n * 2);
      const float v = hits / 16.0f;
      img.setpixel(col, row, &v);
    }
  return img;
}

// The lines centred one under the other, at the largest font size whose
// widest line fits `fill` of the width and whose block fits `fill` of the
// height. Returns an empty message or what went wrong.
std::string text(ImageBuf& img, int n, const std::vector<std::string>& lines, const std::string& font) {
  const double fill = 0.82;
  int size = n;
  std::vector<OIIO::ROI> boxes;
  for (; size >= 8; size = size * 15 / 16) {
    boxes.clear();
    int width = 0, height = 0;
    for (const auto& line : lines) {
      const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(line, size, font);
      if (!box.defined()) return "cannot measure text with the font " + font;
      boxes.push_back(box);
      width = std::max(width, box.width());
    }
    height = static_cast<int>(lines.size()) * size;
    if (width <= fill * n && height <= fill * n) break;
  }
  if (size < 8) return "the text does not fit at any font size";
  img.reset(ImageSpec(n, n, 1, TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::zero(img);
  // One line per `size` pixels; the block is centred vertically.
  const int top = (n - static_cast<int>(lines.size()) * size) / 2;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int y = top + static_cast<int>(i) * size + size / 2;
    const float white = 1.0f;
    if (!OIIO::ImageBufAlgo::render_text(img, n / 2, y, lines[i], size, font, white, OIIO::ImageBufAlgo::TextAlignX::Center,
                                         OIIO::ImageBufAlgo::TextAlignY::Center))
      return "cannot render text: " + img.geterror();
  }
  return "";
}

bool write(const ImageBuf& img, const fs::path& out) {
  const fs::path part = out.parent_path() / (out.stem().string() + ".part" + out.extension().string());
  if (!img.write(part.string(), TypeDesc::UINT8)) {
    std::cerr << "caustic-design-targets: " << out.string() << ": " << img.geterror() << "\n";
    return false;
  }
  fs::rename(part, out);
  std::cout << "wrote " << out.string() << "\n";
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Draw the target pictures of the built-in designed scenes"};
  app.require_subcommand(1);
  int size = 512;
  fs::path out, font;
  std::vector<std::string> lines;
  app.add_option("--size", size, "Pixels per side")->check(CLI::Range(16, 4096));
  CLI::App* logo_cmd = app.add_subcommand("logo", "Ring, star and bar, white on black");
  logo_cmd->add_option("-o,--output", out, "PNG to write")->required();
  CLI::App* text_cmd = app.add_subcommand("text", "Lines of text, white on black");
  text_cmd->add_option("-o,--output", out, "PNG to write")->required();
  text_cmd->add_option("--font", font, "TrueType font file")->required()->check(CLI::ExistingFile);
  text_cmd->add_option("--line", lines, "A line of text (repeat for more lines)")->required();
  CLI11_PARSE(app, argc, argv);

  if (out.extension() != ".png") {
    std::cerr << "caustic-design-targets: --output " << out.string() << ": must end in .png\n";
    return 2;
  }
  ImageBuf img;
  if (logo_cmd->parsed()) {
    img = logo(size);
  } else {
    if (const std::string error = text(img, size, lines, font.string()); !error.empty()) {
      std::cerr << "caustic-design-targets: " << error << "\n";
      return 2;
    }
  }
  return write(img, out) ? 0 : 1;
}
