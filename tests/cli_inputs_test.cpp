// SPDX-License-Identifier: LGPL-2.1-or-later
// The commands' inputs that once crashed, hung, overwrote a file or went
// unsaid: each is now refused with exit status 2 and a message naming the
// flag or key, or warned about, before any work.
#include "causticd_runner.hpp"
#include "png_chunk.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <tuple>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

class CliInputs : public CliTest {
 protected:
  static std::string small() { return " --width 32 --height 32"; }
};

}  // namespace

TEST_F(CliInputs, BenchListsAreCheckedAndBounded) {
  // "abc" once reached a check that threw out of the parser (an abort).
  for (const char* sizes : {"abc", "99999999999", "''"}) expect_rejected("bench --out " + dir_.string() + " --sizes " + sizes, "--sizes");
  expect_rejected("bench --out " + dir_.string() + " --sizes 128,256,384,512,640,768,896,1024,1152", "--sizes: at most 8");
  // Every mesh is built before the timing: not tens of gigabytes of them.
  expect_rejected("bench --out " + dir_.string() + " --meshes 2048,2047,2046", "--meshes: at most");
  EXPECT_FALSE(fs::exists(dir_ / "results.csv"));
}

TEST_F(CliInputs, ABenchFlagTheBenchDoesNotReadIsSaid) {
  const CommandResult r = causticd("bench --out " + dir_.string() +
                                   " --perf --meshes 8 --sizes 128 --frames 1 --photons 5000 --source 64");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: --photons: has no effect with --perf"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: --source: has no effect with --perf"), std::string::npos) << r.output;
}

TEST_F(CliInputs, AKeyPathNamingNoKeyIsRefusedAtOnce) {
  // 20,000 keys deep once took 40 s to build, level by level.
  std::string path = "a";
  for (int i = 0; i < 20000; ++i) path += ".a";
  expect_rejected("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() + small() + " --set " + path +
                      "=1",
                  "a key path of more than 8 keys");
}

TEST_F(CliInputs, AnOutputIsNeverAnInputNorADevice) {
  const fs::path copy = dir_ / "slab.json", mesh = dir_ / "slab.obj";
  fs::copy_file(fs::path(CAUSTIC_ASSET_DIR) / "meshes" / "slab.obj", mesh);
  std::ofstream(copy) << R"({"mesh": "slab.obj", "object": {"flat_face_offset": 1.0}})";
  const auto before = fs::file_size(copy), mesh_before = fs::file_size(mesh);
  expect_rejected("calibrate --scene " + copy.string() + " -o " + copy.string(), "is the command's input");
  expect_rejected("calibrate --scene " + copy.string() + " -o " + mesh.string(), "is the command's input");
  EXPECT_EQ(fs::file_size(copy), before);
  EXPECT_EQ(fs::file_size(mesh), mesh_before);
  // Nor is a pipe, or (as root, who may make one) a device node like /dev/null.
  const fs::path pipe = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  expect_rejected("calibrate --scene " + copy.string() + " -o " + pipe.string(), "is not a regular file");
  EXPECT_TRUE(fs::is_fifo(pipe));
  const fs::path device = dir_ / "null";
  if (::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
    expect_rejected("calibrate --scene " + copy.string() + " -o " + device.string(), "is not a regular file");
    EXPECT_TRUE(fs::is_character_file(device));
  }
  // The designer's target is an input too.
  const fs::path logo = fs::path(CAUSTIC_ASSET_DIR) / "designs" / "design-logo.target.png";
  if (!fs::exists(logo)) GTEST_SKIP() << "built without the designer";
  const fs::path target = dir_ / "target.png";
  fs::copy_file(logo, target);
  const auto target_before = fs::file_size(target);
  expect_rejected("design --target " + target.string() + " -o " + (dir_ / "face.obj").string() + " --report " +
                      target.string(),
                  "is the command's input");
  EXPECT_EQ(fs::file_size(target), target_before);
}

TEST_F(CliInputs, AnOutputNamedTwiceIsRefused) {
  // Written twice, the file kept only the second picture.
  expect_rejected("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() + " -o " + dir_.string() +
                      "/./x.png" + small(),
                  "the same file as --output " + (dir_ / "x.png").string());
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(CliInputs, AnEmptyNameIsRefusedNotTakenAsLeftOut) {
  // calibrate -o '' wrote over the calibration beside the scene.
  const fs::path copy = dir_ / "slab.json";
  fs::copy_file(fs::path(CAUSTIC_ASSET_DIR) / "meshes" / "slab.obj", dir_ / "slab.obj");
  std::ofstream(copy) << R"({"mesh": "slab.obj", "object": {"flat_face_offset": 1.0}})";
  expect_rejected("calibrate --scene " + copy.string() + " -o '' --photons 1000", "--output: must not be empty");
  EXPECT_FALSE(fs::exists(dir_ / "slab.calibration.json"));
  // An instance name left empty was no instance at all.
  expect_rejected("serve --instance '' --scenes-dir " + (dir_ / "absent").string(), "--instance: must not be empty");
  // Nor a folder or an address: --scenes-dir '' served the built-in gallery (bounded: it listened until stopped).
  for (const char* flag : {"--scenes-dir", "--web-dir", "--stun-server", "--ice-address"}) {
    const CommandResult r =
        causticd_with_env("timeout 30", std::string("serve --bind 127.0.0.1 --port 0 ") + flag + " ''");
    EXPECT_EQ(r.status, 2) << flag << ": " << r.output;
    EXPECT_NE(r.output.find(std::string(flag) + ": must not be empty"), std::string::npos) << r.output;
  }
  const fs::path logo = fs::path(CAUSTIC_ASSET_DIR) / "designs" / "design-logo.target.png";
  if (!fs::exists(logo)) GTEST_SKIP() << "built without the designer";
  for (const char* flag : {"--scene-out", "--solid", "--report", "--side-by-side"})
    expect_rejected("design --target " + logo.string() + " -o " + (dir_ / "face.obj").string() + " " + flag + " ''",
                    std::string(flag) + ": must not be empty");
  EXPECT_FALSE(fs::exists(dir_ / "face.obj"));
}

TEST_F(CliInputs, ACalibrationAManualSceneDoesNotReadIsSaid) {
  const CommandResult r = causticd("calibrate --scene " + scene("slab") + " -o " + (dir_ / "c.json").string() +
                                   " --set render.fidelity=manual --photons 1000 --max-side 64 --frames 1");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: render.fidelity is \"manual\": the scene renders as written"), std::string::npos)
      << r.output;
}

TEST_F(CliInputs, ASolidIsNeverResampledOnAGrid) {
  // A grid level of a closed body is an open sheet: calibrate measured the
  // level a solid's scene named, and the engine refused it as no closed surface.
  const std::string calibrate = "calibrate --scene " + scene("biconvex") + " -o " + (dir_ / "c.json").string() +
                                " --set render.light_grid=16 --photons 1000 --max-side 64 --frames 1";
  const CommandResult r = causticd(calibrate + " --set render.mesh_resolution=64");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("1 levels"), std::string::npos) << r.output;
  expect_rejected(calibrate + " --set render.mesh_resolution=64 --set render.fidelity=manual",
                  "render.mesh_resolution: must be 0 for a solid");
}

TEST_F(CliInputs, AFaceOfManyCornersIsNotReadAsATriangle) {
  // The reader counts a face's corners in a byte: 259 came out as 3.
  std::ofstream obj(dir_ / "fan.obj");
  for (int i = 0; i < 259; ++i) obj << "v " << std::cos(i * 0.0243) << " " << std::sin(i * 0.0243) << " 0\n";
  obj << "f";
  for (int i = 1; i <= 259; ++i) obj << " " << i;
  obj << "\n";
  obj.close();
  std::ofstream(dir_ / "fan.json") << R"({"mesh": "fan.obj"})";
  expect_rejected("render --scene " + (dir_ / "fan.json").string() + " -o " + (dir_ / "x.png").string() + small(),
                  "a face of 259 vertices; only triangles are allowed");
}

TEST_F(CliInputs, AKeyWrittenTwiceIsRefusedAndAnAssignmentOverAnotherIsSaid) {
  std::ofstream(dir_ / "twice.json") << R"({"mesh": ")" << CAUSTIC_ASSET_DIR
                                     << R"(/meshes/slab.obj", "focus_distance": 80, "focus_distance": 60})";
  expect_rejected("render --scene " + (dir_ / "twice.json").string() + " -o " + (dir_ / "x.png").string() + small(),
                  "the key \"focus_distance\" is written twice");
  // Said where the second is written, though the name comes earlier as a value and as another object's key.
  std::ofstream(dir_ / "later.json") << "{\"name\": \"light\",\n\"light\": {\"type\": \"directional\"},\n"
                                     << "\"screen\": {\"light\": 1},\n\"light\": {}}";
  expect_rejected("render --scene " + (dir_ / "later.json").string() + " -o " + (dir_ / "x.png").string() + small(),
                  "written twice in one object at line 4, column 1");
  expect_rejected("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() + small() +
                      " --set 'post={\"gamma\":3,\"gamma\":2}'",
                  "post: not valid JSON: the key \"gamma\" is written twice");
  const CommandResult r = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() + small() +
                                   " --set 'post={\"gamma\":3}' --set post.gamma=2");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: post.gamma: post={\"gamma\":3} is overridden by post.gamma=2"), std::string::npos)
      << r.output;
  // A later null resets the object an earlier one wrote into.
  const CommandResult reset = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() +
                                       small() + " --set post.gamma=3 --set post=null");
  EXPECT_EQ(reset.status, 0) << reset.output;
  EXPECT_NE(reset.output.find("warning: post.gamma: post.gamma=3 is overridden by post=null"), std::string::npos)
      << reset.output;
}

// --width and --height set render.width and render.height after every
// --set, wherever they are written: an override is said with the flag the
// user wrote (once quoted as the assignment made of it, "render.width=32").
// A stale calibration's advice to calibrate "with the same --set" is for a
// --set only: calibrate has no --width, and the size is not calibrated.
TEST_F(CliInputs, AFlagThatSetsAKeyIsNamedAsWritten) {
  // Written before the --set, the flag still wins, and says why.
  const CommandResult r = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() +
                                   " --width 32 --height 32 --set render.width=64 --set render.height=48");
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* said : {"warning: render.width: render.width=64 is overridden by --width 32 (a flag applies after "
                           "every --set)",
                           "warning: render.height: render.height=48 is overridden by --height 32", "target 32x32"})
    EXPECT_NE(r.output.find(said), std::string::npos) << said << "\n" << r.output;
  // A calibration beside a scene it was not made for.
  std::ofstream(dir_ / "glass.json") << R"({"mesh": ")" << CAUSTIC_ASSET_DIR
                                     << R"(/meshes/slab.obj", "object": {"ior": 1.6}})";
  fs::copy_file(fs::path(CAUSTIC_ASSET_DIR) / "scenes" / "slab.calibration.json", dir_ / "glass.calibration.json");
  const std::string stale = "render --scene " + (dir_ / "glass.json").string() + " -o " + (dir_ / "x.png").string();
  const CommandResult sized = causticd(stale + small());
  EXPECT_EQ(sized.status, 0) << sized.output;
  EXPECT_NE(sized.output.find("glass.calibration.json was made for other physics"), std::string::npos) << sized.output;
  EXPECT_EQ(sized.output.find("--set"), std::string::npos) << sized.output;
  const CommandResult set = causticd(stale + small() + " --set post.gamma=2");
  EXPECT_NE(set.output.find("makes one for them (with the same --set)"), std::string::npos) << set.output;
}

TEST_F(CliInputs, SeedsAndTheGlDeviceAreCheckedBeforeAnyWork) {
  for (const char* seed : {"-1", "18446744073709551616"})
    expect_rejected("calibrate --scene " + scene("slab") + " -o " + (dir_ / "c.json").string() + " --seed " + seed,
                    "--seed");
  const CommandResult device = causticd_with_env("CAUSTICD_EGL_DEVICE=abc", "render --scene " + scene("slab") + " -o " +
                                                                              (dir_ / "x.png").string() + small());
  EXPECT_EQ(device.status, 2) << device.output;
  EXPECT_NE(device.output.find("CAUSTICD_EGL_DEVICE must be an integer"), std::string::npos) << device.output;
  EXPECT_EQ(device.output.find("renderer:"), std::string::npos) << "refused before a context: " << device.output;
}

TEST_F(CliInputs, TheDesignersFlagsThatDoNothingAreSaid) {
  const std::string target = std::string(CAUSTIC_ASSET_DIR) + "/designs/design-logo.target.png";
  if (!fs::exists(target)) GTEST_SKIP() << "built without the designer";
  const std::string face = " -o " + (dir_ / "face.obj").string() + " --no-check --resolution 16";
  expect_rejected("design --target " + target + face + " --photons 5000", "--photons");  // needs --verify
  expect_rejected("design --target " + target + face + " --focus 1e-300", "--focus");
  const CommandResult forced = causticd("design --target " + target + face + " --force");
  EXPECT_EQ(forced.status, 0) << forced.output;
  EXPECT_NE(forced.output.find("warning: --force: has no effect at --resolution 16"), std::string::npos)
      << forced.output;
}

TEST_F(CliInputs, AStateDirThatIsAFileIsRefused) {
  std::ofstream(dir_ / "a-file") << "x";
  std::ofstream(dir_ / "causticd.conf") << "design_uploads = on\nstate_dir = " << (dir_ / "a-file").string() << "\n";
  expect_rejected("check-config " + (dir_ / "causticd.conf").string(), "state_dir: ");
}

TEST_F(CliInputs, AFaceTheLightMeetsFromBehindIsSaid) {
  // A sine face of slope up to pi/2 (tilted up to 57.5 degrees) in glass of
  // n = 1.0001, the light's angle inside the same as outside: the face shades
  // itself only where it tilts by more than 90 degrees less the light's
  // angle, so at 11.3 degrees from the normal nothing, at 78.7 degrees some.
  const fs::path mesh = dir_ / "sine.obj", scene_file = dir_ / "sine.json";
  {
    std::ofstream obj(mesh);
    constexpr int n = 33;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = -5 + 10.0 * i / (n - 1), y = -5 + 10.0 * j / (n - 1);
        obj << "v " << x << ' ' << y << ' ' << std::sin(std::numbers::pi * x / 2) << "\n";
      }
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
        obj << "f " << a << ' ' << b << ' ' << d << "\nf " << a << ' ' << d << ' ' << c << "\n";
      }
  }
  std::ofstream(scene_file) << R"({"mesh": "sine.obj", "focus_distance": 50,
    "object": {"ior": 1.0001, "flat_face_normal": [0, 0, 1], "flat_face_offset": 3.0},
    "render": {"fidelity": "manual"}})";
  const std::string render = "render --scene " + scene_file.string() + " -o " + (dir_ / "x.png").string() + small();
  const std::string said = "warning: light.direction: the light meets";
  const CommandResult steep = causticd(render + " --set light.direction=[1,0,-0.2]");
  EXPECT_EQ(steep.status, 0) << steep.output;
  EXPECT_NE(steep.output.find(said), std::string::npos) << steep.output;
  const CommandResult gentle = causticd(render + " --set light.direction=[0.2,0,-1]");
  EXPECT_EQ(gentle.status, 0) << gentle.output;
  EXPECT_EQ(gentle.output.find(said), std::string::npos) << gentle.output;
}

namespace {

// A black PNG of w x h pixels by its header, one bit a pixel, with `rows`
// rows of data behind it, stored in zlib's blocks without compression.
std::string black_png(std::uint32_t w, std::uint32_t h, std::uint32_t rows) {
  // Each row: filter 0, then 0 bits; one bit of grey, not interlaced.
  return png_file(w, h, 1, 0, 0, std::string(static_cast<std::size_t>(1 + (w + 7) / 8) * rows, '\0'));
}

// A TIFF of w x h RGB in 256 x 256 tiles, every tile pointing at the same
// 1000 bytes at its end.
std::string tiled_tiff_claiming(std::uint32_t w, std::uint32_t h) {
  const std::uint32_t t = 256, tiles = ((w + t - 1) / t) * ((h + t - 1) / t), entries = 11;
  const std::uint32_t bits = 8 + 2 + 12 * entries + 4, offsets = bits + 6, counts = offsets + 4 * tiles,
                      data = counts + 4 * tiles;
  std::string b("II*\0\x08\0\0\0", 8);
  const auto u16 = [&](std::uint32_t v) { b += static_cast<char>(v & 0xff), b += static_cast<char>(v >> 8 & 0xff); };
  const auto u32 = [&](std::uint32_t v) { u16(v & 0xffff), u16(v >> 16); };
  const auto entry = [&](std::uint32_t tag, std::uint32_t type, std::uint32_t count, std::uint32_t value) {
    u16(tag), u16(type), u32(count), u32(value);  // type 3 is a short, 4 a long
  };
  u16(entries);
  entry(256, 4, 1, w), entry(257, 4, 1, h), entry(258, 3, 3, bits), entry(259, 3, 1, 1), entry(262, 3, 1, 2);
  entry(277, 3, 1, 3), entry(284, 3, 1, 1), entry(322, 4, 1, t), entry(323, 4, 1, t);
  entry(324, 4, tiles, offsets), entry(325, 4, tiles, counts);
  u32(0);
  for (int i = 0; i < 3; ++i) u16(8);
  for (std::uint32_t i = 0; i < tiles; ++i) u32(data);
  for (std::uint32_t i = 0; i < tiles; ++i) u32(t * t * 3);
  return b + std::string(1000, '\x80');
}

}  // namespace

// A header alone says how large a picture is: a few kilobytes declaring
// 16000 x 4000 pixels (within the designer's limits) once had the picture's
// 768 MB set aside before the reader found nothing behind the header, and
// under a memory limit the command aborted. Under half that it is refused
// as the broken file it is.
TEST_F(CliInputs, APictureWhoseHeaderPromisesMoreThanItHoldsIsRefusedBeforeItsMemory) {
  if (!fs::exists(std::string(CAUSTIC_ASSET_DIR) + "/designs/design-logo.target.png"))
    GTEST_SKIP() << "built without the designer";
  const std::string limited = "prlimit --data=" + std::to_string(384 << 20);
  // The PNG's rows are counted as they are inflated, before its reader.
  for (const auto& [name, bytes, said] :
       {std::tuple{"tall.png", black_png(16000, 4000, 1), "the picture is damaged or cut short (its image data ends after"},
        std::tuple{"tall.tif", tiled_tiff_claiming(16000, 4000), "cannot decode the picture ("}}) {
    const fs::path target = dir_ / name;
    std::ofstream(target, std::ios::binary) << bytes;
    const CommandResult r = causticd_with_env(
        limited, "design --target " + target.string() + " -o " + (dir_ / "face.obj").string() + " --no-check");
    EXPECT_EQ(r.status, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find("--target " + target.string() + ": " + said), std::string::npos)
        << name << ": " << r.output;
    EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << name << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "face.obj")) << name;
  }
}

// A picture that is all there but more than the memory holds: refused,
// naming it, where the command aborted on the allocation that failed.
TEST_F(CliInputs, APictureTooLargeForTheMemoryIsRefusedNotAborted) {
  if (!fs::exists(std::string(CAUSTIC_ASSET_DIR) + "/designs/design-logo.target.png"))
    GTEST_SKIP() << "built without the designer";
  const fs::path target = dir_ / "night.png";
  std::ofstream(target, std::ios::binary) << black_png(16000, 4000, 4000);
  const CommandResult r = causticd_with_env("prlimit --data=" + std::to_string(384 << 20),
                                            "design --target " + target.string() + " -o " +
                                                (dir_ / "face.obj").string() + " --no-check");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--target " + target.string() + ": 16000x4000 pixels do not fit in memory"),
            std::string::npos)
      << r.output;
}

// CLI11 reads a number in C's bases: "064" was 52 pixels, "0100" photons
// 64 and "0x40" 64, where the scene's keys and the server's take decimal
// alone. Leading zeros are now only zeros, and any other base is refused.
TEST_F(CliInputs, ANumberFlagIsReadInDecimal) {
  const CommandResult wide = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() +
                                      " --width 064 --height 032");
  EXPECT_EQ(wide.status, 0) << wide.output;
  EXPECT_NE(wide.output.find("target 64x32"), std::string::npos) << wide.output;
  const CommandResult traced = causticd("reference --scene " + scene("slab") + " -o " + (dir_ / "r.exr").string() +
                                        " --set render.width=32 --set render.height=32 --photons 0100 --seed 010");
  EXPECT_EQ(traced.status, 0) << traced.output;
  EXPECT_NE(traced.output.find("photons: 100 traced"), std::string::npos) << traced.output;
  expect_rejected("render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() + " --width 0x40",
                  "--width: must be a whole number in decimal digits, got \"0x40\"");
  expect_rejected("bench --out " + dir_.string() + " --sizes 0x80", "--sizes: must be a whole number in decimal");
  // C's hex floats too: "0x10" was 16 mm, "0x1p-1" half a second.
  expect_rejected("bench --water --out " + dir_.string() + " --seconds 0x1p-1",
                  "--seconds: must be a number in decimal");
  const std::string logo = std::string(CAUSTIC_ASSET_DIR) + "/designs/design-logo.target.png";
  if (!fs::exists(logo)) GTEST_SKIP() << "built without the designer";
  expect_rejected("design --target " + logo + " -o " + (dir_ / "face.obj").string() + " --no-check --size 0x10",
                  "--size: must be a number in decimal notation, got \"0x10\"");
  EXPECT_FALSE(fs::exists(dir_ / "face.obj"));
}

// A named flag applies after every --set, wherever each was written, as
// render's do; the --set it overrides is said. The parser handed the flags
// over before the --set items, so the --set won (the comment promised the
// line's order, which the parser does not keep).
TEST_F(CliInputs, AServeFlagAppliesAfterEverySet) {
  // A gallery of one small scene: listening in well under a second, so the
  // bound below leaves room on a loaded machine.
  fs::create_directories(dir_ / "scenes");
  fs::create_directories(dir_ / "meshes");
  fs::copy_file(scene("slab"), dir_ / "scenes" / "slab.json");
  fs::copy_file(fs::path(CAUSTIC_ASSET_DIR) / "meshes" / "slab.obj", dir_ / "meshes" / "slab.obj");
  // Were the --set to win, the server would try 192.0.2.1 (no host's) and exit.
  const CommandResult r =
      causticd_with_env("timeout 10", "serve --port 0 --bind 127.0.0.1 --set bind_address=192.0.2.1 --scenes-dir " +
                                          (dir_ / "scenes").string());
  EXPECT_NE(r.output.find("listening on http://127.0.0.1:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bind_address: the value set at --set bind_address is overridden by --bind"), std::string::npos)
      << r.output;
}
