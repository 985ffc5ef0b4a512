// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd design` as a user runs it: a small design end to end (its scene
// renders with `causticd render` as written), and every kind of bad target
// or flag rejected with exit 2, a message naming the file or flag, and no
// output left behind.
#include "causticd_runner.hpp"

#include "caustic/image_io.hpp"
#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

class DesignCli : public ScratchDirTest {
 protected:

  // A 48x48 grey ramp with a bright disc, as an 8-bit PNG.
  fs::path good_target() const {
    caustic::Rgba8Image img{48, 48, std::vector<std::uint8_t>(48 * 48 * 4, 255)};
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        const bool disc = (x - 30) * (x - 30) + (y - 18) * (y - 18) < 64;
        const auto v = static_cast<std::uint8_t>(disc ? 255 : 40 + 3 * x);
        for (int c = 0; c < 3; ++c) img.pixels[(y * 48 + x) * 4 + c] = v;
      }
    const fs::path p = dir_ / "target.png";
    caustic::write_png(img, p);
    return p;
  }

  // Expects exit 2, `fragment` in the message and no face or scene written.
  void expect_rejected(const std::string& args, const std::string& fragment) {
    const fs::path face = dir_ / "face.obj";
    const CommandResult run = causticd("design " + args + " -o " + face.string());
    EXPECT_EQ(run.status, 2) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(fragment), std::string::npos) << args << "\n" << run.output;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name.rfind("target", 0) == 0 || name.rfind("bad", 0) == 0) << "left behind: " << name;
    }
  }

};

}  // namespace

TEST_F(DesignCli, DesignsAFaceWhoseSceneRendersAsWritten) {
  const fs::path target = good_target(), face = dir_ / "face.obj", scene = dir_ / "scenes" / "face.json";
  fs::create_directories(dir_ / "scenes");
  const fs::path solid = dir_ / "solid.obj", report = dir_ / "report.json", pair = dir_ / "pair.png";
  const CommandResult r = causticd("design --target " + target.string() + " -o " + face.string() + " --scene-out " +
                         scene.string() + " --resolution 32 --solid " + solid.string() + " --report " +
                         report.string() + " --side-by-side " + pair.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("engine: SSIM"), std::string::npos) << r.output;
  for (const auto& p : {face, scene, solid, report, pair}) EXPECT_TRUE(fs::exists(p)) << p;
  const caustic::Scene s = caustic::load_scene(scene);
  EXPECT_EQ(s.mesh, "../face.obj");
  const caustic::Mesh m = caustic::load_obj(s.mesh_path());
  EXPECT_EQ(m.positions.size(), 33u * 33u);
  EXPECT_DOUBLE_EQ(s.screen.center.z, -200.0);
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["tir_vertices"], 0);
  EXPECT_GT(j["engine"]["ssim"].get<double>(), 0.8);
  const fs::path png = dir_ / "render.png";
  const CommandResult render = causticd("render --scene " + scene.string() + " -o " + png.string() + " --width 64 --height 64");
  EXPECT_EQ(render.status, 0) << render.output;
  // As written: its light lands on the screen (the tone-mapped picture is not black).
  const caustic::HdrImage shown = caustic::read_hdr_image(png);  // the PNG's first channel, 0 to 1
  int lit = 0;
  for (float v : shown.pixels) lit += v > 16 / 255.0f;
  EXPECT_GT(lit, 64 * 64 / 8) << "the designed scene renders dark";
}

TEST_F(DesignCli, DesignsInColourATintedFaceWhoseRenderIsInColour) {
  // Top half blue, bottom half orange.
  caustic::Rgba8Image img{48, 48, std::vector<std::uint8_t>(48 * 48 * 4, 255)};
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const std::uint8_t blue[3] = {30, 60, 250}, orange[3] = {250, 140, 20};
      for (int c = 0; c < 3; ++c) img.pixels[(y * 48 + x) * 4 + c] = y < 24 ? blue[c] : orange[c];
    }
  const fs::path target = dir_ / "target.png", face = dir_ / "face.obj", report = dir_ / "report.json",
                 pair = dir_ / "pair.png", render = dir_ / "render.exr";
  caustic::write_png(img, target);
  const CommandResult r = causticd("design --colour --target " + target.string() + " -o " + face.string() +
                                   " --resolution 32 --report " + report.string() + " --side-by-side " + pair.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("chromaticity error"), std::string::npos) << r.output;
  EXPECT_TRUE(caustic::tinted(caustic::load_obj(face)));
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["colour"], true);
  EXPECT_LT(j["engine"]["colour"]["chromaticity_error"].get<double>(), 0.02) << j.dump();
  // The scene renders RGB: the top of the screen blue, the bottom orange.
  const CommandResult shown = causticd("render --scene " + (dir_ / "face.json").string() + " -o " + render.string() +
                                       " --width 32 --height 32");
  ASSERT_EQ(shown.status, 0) << shown.output;
  const caustic::RgbHdrImage rgb = caustic::read_rgb_image(render);
  double top[3] = {0, 0, 0}, bottom[3] = {0, 0, 0};
  for (int y = 4; y < 28; ++y)
    for (int x = 4; x < 28; ++x)
      if (y < 14 || y >= 18)
        for (int c = 0; c < 3; ++c) (y < 16 ? top : bottom)[c] += rgb.pixels[3 * (std::size_t(y) * 32 + x) + c];
  EXPECT_GT(top[2], 2 * top[0]) << "blue above";
  EXPECT_GT(bottom[0], 2 * bottom[2]) << "orange below";
}

TEST_F(DesignCli, RejectsBadTargetsAndFlags) {
  const fs::path target = good_target();
  const std::string t = " --target " + target.string();
  expect_rejected("--target " + (dir_ / "bad-missing.png").string(), "bad-missing.png");
  {
    std::ofstream(dir_ / "bad-empty.png");
  }
  expect_rejected("--target " + (dir_ / "bad-empty.png").string(), "bad-empty.png: is empty");
  {
    caustic::Rgba8Image black{16, 16, std::vector<std::uint8_t>(16 * 16 * 4, 0)};
    caustic::write_png(black, dir_ / "bad-black.png");
  }
  expect_rejected("--target " + (dir_ / "bad-black.png").string(), "all black");
  {
    caustic::HdrImage nan{16, 16, std::vector<float>(256, 1.0f)};
    nan.pixels[17] = std::numeric_limits<float>::quiet_NaN();
    caustic::write_exr(nan, dir_ / "bad-nan.exr");
    nan.pixels[17] = std::numeric_limits<float>::infinity();
    caustic::write_exr(nan, dir_ / "bad-inf.exr");
  }
  expect_rejected("--target " + (dir_ / "bad-nan.exr").string(), "bad-nan.exr");
  expect_rejected("--target " + (dir_ / "bad-inf.exr").string(), "infinite");
  {
    // A 20000 x 20000 grey PNM: only its header is read before the size check.
    std::ofstream huge(dir_ / "bad-huge.pgm", std::ios::binary);
    huge << "P5\n20000 20000\n255\n" << std::string(1024, '\x80');
  }
  expect_rejected("--target " + (dir_ / "bad-huge.pgm").string(), "too large");
  expect_rejected(t + " --resolution 5000", "--resolution");
  expect_rejected(t + " --resolution 2048", "--force");
  expect_rejected(t + " --focus -5", "--focus");
  expect_rejected(t + " --ior 0.5", "--ior");
  expect_rejected(t + " --black-floor 0", "--black-floor");
  // Two outputs at one path: refused before anything is written, not the second's content under the first's name.
  expect_rejected(t + " --report " + (dir_ / "face.json").string(), "--report " + (dir_ / "face.json").string() +
                                                                        ": the same file as --scene-out");
  expect_rejected(t + " --solid " + (dir_ / "face.obj").string(), "the same file as --output");
  expect_rejected(t + " --scene-out " + (dir_ / "x.json").string() + " --report " + (dir_ / "." / "x.json").string(),
                  "--report");
}

TEST_F(DesignCli, RefusesGlassItsSceneCouldNotRenderAndOutputsItCannotWrite) {
  const std::string t = " --target " + good_target().string() + " --resolution 16 --no-check";
  // Each once written with exit 0 and refused by `render` afterwards.
  expect_rejected(t + " --size 1e-300", "--size");
  expect_rejected(t + " --size 10000", "lies within the glass");      // a relief of metres, the screen 200 mm away
  expect_rejected(t + " --focus 1e-300", "--focus: must be in [0.01");  // once a face of NaN, blamed on the picture
  expect_rejected(t + " --size 2 --focus 0.02", "lies within the glass");
  // Outputs tried before the solve (once found after it, exit 1).
  fs::create_directory(dir_ / "bad-folder.json");
  expect_rejected(t + " --report " + (dir_ / "bad-folder.json").string(),
                  "--report " + (dir_ / "bad-folder.json").string() + ": is a folder");
  expect_rejected(t + " --solid " + (dir_ / "bad-none" / "s.obj").string(), "does not exist");
  expect_rejected(t + " --scene-out /proc/x.json", "--scene-out /proc/x.json: cannot be written");
  // What passes these renders as written.
  const fs::path face = dir_ / "face.obj";
  const CommandResult design = causticd("design" + t + " --size 2 --focus 5 -o " + face.string());
  ASSERT_EQ(design.status, 0) << design.output;
  const CommandResult render =
      causticd("render --scene " + (dir_ / "face.json").string() + " -o " + (dir_ / "face.exr").string());
  EXPECT_EQ(render.status, 0) << render.output;
}

TEST_F(DesignCli, WritesTheGivenNameAndDescriptionIntoTheScene) {
  const fs::path target = good_target(), face = dir_ / "face.obj", scene = dir_ / "face.json";
  const CommandResult r = causticd("design --target " + target.string() + " -o " + face.string() +
                                   " --resolution 16 --no-check --name 'Chelsea the cat' --description 'A cat, in light.'");
  ASSERT_EQ(r.status, 0) << r.output;
  const caustic::Scene s = caustic::load_scene(scene);
  EXPECT_EQ(s.name, "Chelsea the cat");
  EXPECT_EQ(s.description, "A cat, in light.");
}

TEST_F(DesignCli, RejectsNamesAndDescriptionsTheSceneParserWouldNot) {
  const std::string t = " --target " + good_target().string();
  expect_rejected(t + " --name ''", "--name: must not be empty");
  expect_rejected(t + " --name " + std::string(201, 'n'), "--name: is longer than 200");
  expect_rejected(t + " --name 'tab\there'", "--name: must not contain control characters");
  expect_rejected(t + " --name 'bad \xff byte'", "--name: must be valid UTF-8");
  expect_rejected(t + " --description " + std::string(2001, 'd'), "--description: is longer than 2000");
  expect_rejected(t + " --description 'two\nlines'", "--description: must not contain control characters");
  // The limits themselves are accepted (no picture check needed for that).
  const CommandResult r = causticd("design" + t + " -o " + (dir_ / "face.obj").string() + " --resolution 16 --no-check --name " +
                                   std::string(200, 'n') + " --description ''");
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST_F(DesignCli, ADesignThatDidNotConvergeFailsUnlessAcceptedAndSaysWhy) {
  // One bright pixel on black at a floor of 1e-6: the transport cannot put
  // a millionth of the light on most of the picture and stalls far from it.
  caustic::Rgba8Image img{32, 32, std::vector<std::uint8_t>(32 * 32 * 4, 0)};
  for (int c = 0; c < 4; ++c) img.pixels[(16 * 32 + 16) * 4 + c] = 255;
  const fs::path target = dir_ / "target-dot.png";
  caustic::write_png(img, target);
  const fs::path face = dir_ / "dot.obj", report = dir_ / "dot-report.json";
  const std::string args = "design --target " + target.string() + " --resolution 32 --black-floor 1e-6 --no-check -o " +
                           face.string() + " --report " + report.string();
  const CommandResult refused = causticd(args);
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_NE(refused.output.find("the design is not written: the transport did not converge"), std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(face));
  EXPECT_FALSE(fs::exists(report));
  const CommandResult accepted = causticd(args + " --accept-unconverged");
  EXPECT_EQ(accepted.status, 0) << accepted.output;
  EXPECT_NE(accepted.output.find("--accept-unconverged"), std::string::npos) << accepted.output;
  ASSERT_TRUE(fs::exists(report));
  const auto written = nlohmann::json::parse(std::ifstream(report));
  EXPECT_FALSE(written["converged"].get<bool>() && written["snell_settled"].get<bool>()) << written.dump();
}

// A kernel file says it holds nothing and then waits on a read for what may
// never come: /proc/kmsg held the command (and the image library probing
// it with every format's reader) until killed. Refused by its size, unread.
TEST_F(DesignCli, AKernelFileThatWaitsOnAReadIsRefusedUnread) {
  if (!fs::exists("/proc/kmsg")) GTEST_SKIP() << "no /proc/kmsg here";
  const CommandResult run =
      causticd_with_env("timeout 60", "design --target /proc/kmsg -o " + (dir_ / "face.obj").string());
  EXPECT_EQ(run.status, 2) << run.output;
  EXPECT_NE(run.output.find("--target /proc/kmsg: is empty"), std::string::npos) << run.output;
}

TEST_F(DesignCli, ADamagedPngIsSaidInOneLineThatNamesItAndWhy) {
  // libpng printed "libpng error: IDAT: ..." on its own line beside the
  // command's message.
  std::ifstream in(good_target(), std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const fs::path cut = dir_ / "bad-cut.png";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 20);
  const CommandResult run = causticd("design --no-check --target " + cut.string() + " -o " + (dir_ / "face.obj").string());
  EXPECT_EQ(run.status, 2) << run.output;
  EXPECT_EQ(run.output.find("libpng"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find('\n'), run.output.size() - 1) << run.output;
  EXPECT_NE(run.output.find("--target " + cut.string() + ": the picture is damaged or cut short (cut short: "),
            std::string::npos)
      << run.output;
}

TEST_F(DesignCli, AMultiPageTiffIsDesignedFromItsFirstPageWithAWarning) {
  // Its first page the good target, its second black: designed, the second
  // is named as not read.
  const caustic::HdrImage first = caustic::read_hdr_image(good_target());
  const fs::path tiff = dir_ / "target-pages.tif";
  auto out = OIIO::ImageOutput::create(tiff.string());
  std::vector<OIIO::ImageSpec> specs(2, OIIO::ImageSpec(48, 48, 1, OIIO::TypeDesc::FLOAT));
  ASSERT_TRUE(out && out->open(tiff.string(), 2, specs.data()) &&
              out->write_image(OIIO::TypeDesc::FLOAT, first.pixels.data()));
  const std::vector<float> black(48 * 48, 0.0f);
  ASSERT_TRUE(out->open(tiff.string(), specs[1], OIIO::ImageOutput::AppendSubimage) &&
              out->write_image(OIIO::TypeDesc::FLOAT, black.data()) && out->close());
  const CommandResult run = causticd("design --no-check --resolution 16 --target " + tiff.string() + " -o " +
                                     (dir_ / "face.obj").string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("causticd design: warning: --target " + tiff.string() +
                            ": holds 2 images (pages, frames or parts); only the first is designed\n"),
            std::string::npos)
      << run.output;
}

// The outputs are written as `render` writes its own: under hidden names,
// renamed together once all are complete. Through a link (one whose file is
// still to be made included) the link stays and its file gets the face; a
// file of the user's named like a sibling of an output is nobody's
// temporary and stays as it was.
TEST_F(DesignCli, OutputsGoThroughLinksAndLeaveNoOtherFile) {
  const fs::path target = good_target();
  fs::create_directories(dir_ / "real");
  fs::create_symlink("real/f.obj", dir_ / "face.obj");
  std::ofstream(dir_ / "face.part.obj") << "mine";
  const CommandResult r = causticd("design --target " + target.string() + " -o " + (dir_ / "face.obj").string() +
                                   " --resolution 16 --no-check --report " + (dir_ / "report.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(dir_ / "face.obj"));
  EXPECT_EQ(caustic::load_obj(dir_ / "real" / "f.obj").positions.size(), 17u * 17u);
  std::ifstream mine(dir_ / "face.part.obj");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(mine), {}), "mine");
  for (const fs::path& folder : {dir_, dir_ / "real"})
    for (const auto& entry : fs::directory_iterator(folder))
      EXPECT_NE(entry.path().filename().string().front(), '.') << "left behind: " << entry.path();
  const CommandResult render = causticd("render --scene " + (dir_ / "face.json").string() + " -o " +
                                        (dir_ / "face.exr").string() + " --width 32 --height 32");
  EXPECT_EQ(render.status, 0) << render.output;
}
