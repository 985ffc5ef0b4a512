// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd render` as a user runs it: every built-in scene to EXR and PNG,
// and every kind of bad input rejected with a message and a non-zero exit.
#include "causticd_runner.hpp"

#include "caustic/image_io.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

class Cli : public CliTest {};

}  // namespace

// Every scene of the gallery renders, lit, and without a warning that its
// light misses the screen (the prism's, judged on a flat slab, once was).
TEST_F(Cli, RendersEveryBuiltInSceneToExrAndPng) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(fs::path(scene("lens")).parent_path()))
    if (entry.path().extension() == ".json" && entry.path().stem().extension().empty())  // not x.calibration.json
      names.push_back(entry.path().stem().string());
  EXPECT_GE(names.size(), 5u);
  for (const std::string& name : names) {
    const fs::path exr = dir_ / (name + ".exr"), png = dir_ / (name + ".png");
    const CommandResult r = causticd("render --scene " + scene(name) + " -o " + exr.string() + " -o " + png.string() +
                           " --width 256 --height 256");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("render time:"), std::string::npos) << r.output;
    for (const char* key : {"warning: light.", "warning: screen.", "warning: object.material"})
      EXPECT_EQ(r.output.find(key), std::string::npos) << name << "\n" << r.output;
    const caustic::HdrImage hdr = caustic::read_hdr_image(exr);
    EXPECT_EQ(hdr.width, 256);
    double sum = 0;
    for (float v : hdr.pixels) {
      ASSERT_TRUE(std::isfinite(v));
      sum += v;
    }
    EXPECT_GT(sum, 0.0) << name;
    const caustic::HdrImage ldr = caustic::read_hdr_image(png);
    EXPECT_EQ(ldr.width, 256);
    EXPECT_EQ(ldr.height, 256);
  }
}

TEST_F(Cli, ASpectralSceneRendersToAnRgbExrAndAColouredPng) {
  const fs::path exr = dir_ / "prism.exr", png = dir_ / "prism.png";
  const CommandResult r = causticd("render --scene " + scene("prism") + " -o " + exr.string() + " -o " + png.string() +
                                   " --width 128 --height 128");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("spectral: 16 wavelengths"), std::string::npos) << r.output;
  // The fan's violet edge and red edge: a column where blue leads, one where red does.
  for (const fs::path& file : {exr, png}) {
    const caustic::RgbHdrImage rgb = caustic::read_rgb_image(file);
    bool blue = false, red = false;
    for (std::size_t i = 0; i < rgb.pixels.size(); i += 3) {
      const float R = rgb.pixels[i], B = rgb.pixels[i + 2];
      blue = blue || B > 2 * R + 1e-3f;
      red = red || R > 2 * B + 1e-3f;
    }
    EXPECT_TRUE(blue && red) << file;
  }
  // A grey scene's EXR stays one channel, read as grey.
  const fs::path slab = dir_ / "slab.exr";
  ASSERT_EQ(causticd("render --scene " + scene("slab") + " -o " + slab.string() + " --width 64 --height 64").status, 0);
  const caustic::RgbHdrImage grey = caustic::read_rgb_image(slab);
  for (std::size_t i = 0; i < grey.pixels.size(); i += 3) ASSERT_EQ(grey.pixels[i], grey.pixels[i + 2]);
}

TEST_F(Cli, SlabExrHoldsTheFresnelTransmittance) {
  const fs::path exr = dir_ / "slab.exr";
  ASSERT_EQ(causticd("render --scene " + scene("slab") + " -o " + exr.string() + " --width 128 --height 128").status, 0);
  const caustic::HdrImage hdr = caustic::read_hdr_image(exr);
  EXPECT_NEAR(hdr.at(64, 64), 0.9216, 1e-3);  // two faces at normal incidence, n = 1.5
  EXPECT_EQ(hdr.at(1, 1), 0.0f);              // outside the slab's shadow
}

TEST_F(Cli, SetOverridesSceneKeys) {
  const fs::path exr = dir_ / "slab.exr";
  ASSERT_EQ(causticd("render --scene " + scene("slab") + " -o " + exr.string() +
                     " --width 64 --height 64 --set render.fidelity=manual --set render.fresnel=false")
                .status,
            0);
  EXPECT_NEAR(caustic::read_hdr_image(exr).at(32, 32), 1.0, 1e-4);
}

TEST_F(Cli, RejectsBadInputWithAMessage) {
  const std::string out = " -o " + (dir_ / "x.png").string();
  expect_rejected("render --scene /nonexistent.json" + out, "nonexistent");
  expect_rejected("render --scene " + scene("lens") + " -o " + (dir_ / "x.jpg").string(), ".exr or .png");
  expect_rejected("render --scene " + scene("lens") + out + " --set object.ior=-3", "object.ior");
  expect_rejected("render --scene " + scene("lens") + out + " --set object.colour=red", "object.colour: unknown key");
  expect_rejected("render --scene " + scene("lens") + out + " --set object.ior", "key.path=value");
  expect_rejected("render --scene " + scene("lens") + out + " --width 5", "width");
  expect_rejected("render --scene " + scene("lens"), "--output");
  expect_rejected("render" + out, "--scene");
  expect_rejected("paint", "subcommand");

  std::ofstream(dir_ / "broken.json") << "{\"mesh\": ";
  expect_rejected("render --scene " + (dir_ / "broken.json").string() + out, "not valid JSON");
  std::ofstream(dir_ / "nomesh.json") << R"({"mesh": "missing.obj"})";
  expect_rejected("render --scene " + (dir_ / "nomesh.json").string() + out, "cannot read mesh file missing.obj");
  std::ofstream(dir_ / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  std::ofstream(dir_ / "quad.json") << R"({"mesh": "quad.obj"})";
  expect_rejected("render --scene " + (dir_ / "quad.json").string() + out, "only triangles");
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  // A folder that is not there is found before the work, not after it.
  const std::string nowhere = (dir_ / "missing-folder" / "x").string();
  expect_rejected("render --scene " + scene("lens") + " -o " + nowhere + ".png", "--output " + nowhere + ".png: folder");
  expect_rejected("reference --scene " + scene("slab") + " -o " + nowhere + ".exr", "--output " + nowhere + ".exr: folder");
  // So is an output that is a folder or cannot be made (once exit 1, after the work).
  fs::create_directories(dir_ / "folder.png");
  expect_rejected("render --scene " + scene("lens") + " -o " + (dir_ / "folder.png").string(), "folder.png: is a folder");
  expect_rejected("render --scene " + scene("lens") + " -o /proc/x.png", "--output /proc/x.png: cannot be written");
  expect_rejected("reference --scene " + scene("slab") + " -o /proc/r.exr", "--output /proc/r.exr: cannot be written");
  for (const char* seed : {"-1", "99999999999999999999999", "18446744073709551616", "1.5"})  // "-1" was 2^64 - 1
    expect_rejected("reference --scene " + scene("slab") + " -o " + (dir_ / "r.exr").string() + " --seed " + seed,
                    "--seed");
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  expect_rejected("calibrate --scene " + scene("slab") + " -o " + nowhere + ".json", "--output " + nowhere + ".json: folder");
}

TEST_F(Cli, KeysThatAreNotUsedAsWrittenAreWarnedAbout) {
  // A key its section leaves unused (the tone map is global), and a width
  // set twice (--set, then --width): both said, the render still made.
  const fs::path png = dir_ / "w.png";
  const CommandResult r = causticd("render --scene " + scene("slab") + " -o " + png.string() +
                                   " --set post.local_strength=0.9 --set render.width=32 --width 64 --height 64");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: post.local_strength is used only by post.tone_map \"local\""), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("warning: render.width: render.width=32 is overridden by --width 64"), std::string::npos)
      << r.output;
  EXPECT_EQ(caustic::read_hdr_image(png).width, 64);
  // A light that travels away from the screen leaves the picture black:
  // said, naming the key, as the server says it of a session's scene.
  const CommandResult away = causticd("render --scene " + scene("slab") + " -o " + png.string() +
                                      " --width 32 --height 32 --set light.direction=[0,0,1]");
  ASSERT_EQ(away.status, 0) << away.output;
  EXPECT_NE(away.output.find("warning: light.direction: no light reaches the screen"), std::string::npos)
      << away.output;
  // The built-in scenes write nothing that is not used.
  const CommandResult clean = causticd("render --scene " + scene("lens") + " -o " + png.string() + " --width 64 --height 64");
  ASSERT_EQ(clean.status, 0) << clean.output;
  EXPECT_EQ(clean.output.find("warning"), std::string::npos) << clean.output;
}

// The slab's screen follows the light, and its file places it by
// focus_distance. A centre set off the light's footprint overrides
// focus_distance (said, though the two keys are written in different
// places) and is itself moved back in its plane (said: it was not); the
// reference traces the screen where the render has it (it traced the
// written centre, 30 mm aside, where no light lands).
TEST_F(Cli, AScreenThatFollowsTheLightIsSaidAndTracedWhereItRenders) {
  const std::string aside = " --set screen.center=[30,0,-50]";
  const CommandResult r = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "f.png").string() +
                                   " --width 32 --height 32" + aside);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: focus_distance places the screen when screen.center is absent"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("warning: screen.center sets only the screen plane while screen.follow_light is true"),
            std::string::npos)
      << r.output;
  const fs::path exr = dir_ / "f.exr";
  const CommandResult ref = causticd("reference --scene " + scene("slab") + " -o " + exr.string() +
                                     " --photons 100000 --set render.width=32 --set render.height=32" + aside);
  ASSERT_EQ(ref.status, 0) << ref.output;
  EXPECT_NEAR(caustic::read_hdr_image(exr).at(16, 16), 0.9216, 0.05);
}

TEST_F(Cli, EglPlatformChoiceIsCheckedAndExplained) {
  const std::string args = " render --scene " + scene("slab") + " -o " + (dir_ / "x.png").string() +
                           " --width 32 --height 32";
  CommandResult bad = causticd_with_env("CAUSTICD_EGL_PLATFORM=vulkan", args);
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("CAUSTICD_EGL_PLATFORM must be automatic, device or surfaceless"), std::string::npos)
      << bad.output;
  // On a machine without a GPU asking for one is a clear error; with one it renders on it.
  CommandResult device = causticd_with_env("CAUSTICD_EGL_PLATFORM=device", args);
  if (device.status == 0)
    EXPECT_EQ(device.output.find("llvmpipe"), std::string::npos) << device.output;
  else
    EXPECT_NE(device.output.find("no hardware EGL device"), std::string::npos) << device.output;
  CommandResult cpu = causticd_with_env("CAUSTICD_EGL_PLATFORM=surfaceless", args);
  EXPECT_EQ(cpu.status, 0) << cpu.output;
}

TEST_F(Cli, ReferenceTracesToExrAndRejectsBadInput) {
  const fs::path exr = dir_ / "ref.exr";
  const CommandResult r = causticd("reference --scene " + scene("slab") + " -o " + exr.string() +
                                   " --photons 250000 --set render.width=64 --set render.height=64");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("M photons/s"), std::string::npos) << r.output;
  const caustic::HdrImage hdr = caustic::read_hdr_image(exr);
  EXPECT_NEAR(hdr.at(32, 32), 0.9216, 0.05);
  expect_rejected("reference --scene " + scene("slab") + " -o " + (dir_ / "ref.png").string(), ".exr");
  expect_rejected("reference --scene " + scene("slab") + " -o " + exr.string() + " --photons 0", "photons");
  expect_rejected("reference --scene " + scene("slab") + " -o " + exr.string() + " --set object.ior=0", "object.ior");
}

std::vector<std::string> csv_lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(Cli, BenchWritesResultsAndCharts) {
  const CommandResult r = causticd("bench --out " + dir_.string() +
                                   " --photons 20000 --frames 1 --meshes 16 --sizes 128 --source 128");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto results = csv_lines(dir_ / "results.csv");
  ASSERT_FALSE(results.empty());
  EXPECT_EQ(results[0], "setup,method,mesh,pixels,ray_ms,post_ms,relative_l1,relative_rmse,ssim");
  EXPECT_EQ(results.size(), 8u);  // the header and seven methods over four set-ups, one mesh, one size
  EXPECT_GT(fs::file_size(dir_ / "accuracy.png"), 1000u);
  EXPECT_GT(fs::file_size(dir_ / "accuracy.svg"), 1000u);
  EXPECT_GT(fs::file_size(dir_ / "convergence.png"), 1000u);
  const auto convergence = csv_lines(dir_ / "convergence.csv");
  ASSERT_FALSE(convergence.empty());
  EXPECT_EQ(convergence[0], "series,x,relative_l1");
  int reference_rows = 0;
  for (const auto& line : convergence) reference_rows += line.rfind("reference,", 0) == 0;
  EXPECT_EQ(reference_rows, 4);  // photons/512 .. photons/8, four steps of 4x
  expect_rejected("bench --out " + dir_.string() + " --sizes 100", "--sizes");
}

TEST_F(Cli, PerfBenchWritesFrameCosts) {
  const CommandResult r = causticd("bench --perf --out " + dir_.string() + " --frames 1 --meshes 16 32 --sizes 128");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto perf = csv_lines(dir_ / "perf.csv");
  ASSERT_FALSE(perf.empty());
  EXPECT_EQ(perf[0], "mesh,pixels,triangles,ray_ms,post_ms,rgba_readback_ms,i420_ms");
  EXPECT_EQ(perf.size(), 3u);  // the header and two meshes at one size
  EXPECT_GT(fs::file_size(dir_ / "perf.png"), 1000u);
}

TEST_F(Cli, BenchTriesItsFolderFirstAndChartsInAnyFolderName) {
  // A quote in the folder's name once broke the shell line that ran gnuplot: no chart.
  const fs::path odd = dir_ / "it's a 'folder' $HOME";
  std::string quoted = "'";  // for the shell that runs the command
  for (const char c : odd.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  const CommandResult r = causticd("bench --perf --out " + quoted + " --frames 1 --meshes 16 --sizes 128");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(odd / "perf.png"), 1000u) << r.output;
  // A folder that cannot be made or written is refused before any frame (once exit 1, after the work).
  std::ofstream(dir_ / "a-file") << "x";
  expect_rejected("bench --perf --out " + (dir_ / "a-file").string(), "--out " + (dir_ / "a-file").string() + ": ");
  expect_rejected("bench --out /proc/self/bench", "--out /proc/self/bench: ");
  expect_rejected("bench --spectral --out /proc/bench", "--out /proc/bench: cannot be made a folder");
}

TEST_F(Cli, WaterBenchWritesFrameCostsAndTheLastFrames) {
  const CommandResult r =
      causticd("bench --water --out " + dir_.string() +
               " --grids 32,48 --sizes 128 --seconds 0.2 --setups gpu,cpu --divisors 1,2");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = csv_lines(dir_ / "water.csv");
  ASSERT_EQ(rows.size(), 9u);  // the header and two grids at one size, each set up both ways, full and preview
  EXPECT_EQ(rows[0], "grid,pixels,setup,divisor,steps_per_frame,sim_ms,mesh_ms,caustic_ms,post_ms,i420_ms,frame_ms,"
                     "frame_p95_ms,over_budget,frames");
  EXPECT_EQ(rows[1].rfind("32,128,gpu,1,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("32,128,gpu,2,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind("32,128,cpu,1,", 0), 0u) << rows[3];
  EXPECT_GT(fs::file_size(dir_ / "water-48-128-cpu-p2.png"), 100u);
  expect_rejected("bench --water --out " + dir_.string() + " --setups sideways", "--setups");
  expect_rejected("bench --water --out " + dir_.string() + " --divisors 0", "--divisors");
  expect_rejected("bench --out " + dir_.string() + " --divisors 2", "--water");
  expect_rejected("bench --out " + dir_.string() + " --grids 64", "--water");
  expect_rejected("bench --water --out " + dir_.string() + " --grids 8", "--grids");
  expect_rejected("bench --water --out " + dir_.string() + " --seconds 0", "--seconds");
  expect_rejected("bench --water --out " + dir_.string() + " --seconds nan", "--seconds");  // once a crash
  expect_rejected("bench --water --perf --out " + dir_.string(), "--water");
}

TEST_F(Cli, ASolidsOwnLightGridBoundsTheGridAutoChooses) {
  // A copy of the biconvex lens at a 128^2 light grid, calibrated at 64^2
  // and 128^2: the scene's own grid, or one written beside it, is the
  // finest that auto may take (a calibration made at a finer grid stays
  // usable, the fingerprint leaves the grid out).
  nlohmann::json j = nlohmann::json::parse(std::ifstream(scene("biconvex")));
  j["mesh"] = (fs::path(CAUSTIC_ASSET_DIR) / "meshes" / "biconvex.obj").string();
  j["render"]["light_grid"] = 128;
  std::ofstream(dir_ / "biconvex.json") << j.dump();
  const std::string lens = (dir_ / "biconvex.json").string();
  const CommandResult c = causticd("calibrate --scene " + lens + " --photons 200000 --max-side 64 --frames 1");
  ASSERT_EQ(c.status, 0) << c.output;
  const auto cal = nlohmann::json::parse(std::ifstream(dir_ / "biconvex.calibration.json"));
  std::set<int> grids;
  for (const auto& e : cal["entries"]) grids.insert(e["light_grid"].get<int>());
  ASSERT_EQ(grids, (std::set<int>{64, 128})) << c.output;
  const std::string out = " -o " + (dir_ / "b.png").string() + " --width 64 --height 64";
  const CommandResult at64 = causticd("render --scene " + lens + out + " --set render.light_grid=64");
  ASSERT_EQ(at64.status, 0) << at64.output;
  EXPECT_NE(at64.output.find("light grid 64^2"), std::string::npos) << at64.output;
  EXPECT_NE(at64.output.find("no finer than the scene's own grid"), std::string::npos) << at64.output;
  // The control: the scene's own 128^2 is what auto takes unbounded (64^2
  // misses the target at the streamed size), so the 64^2 above is the bound's.
  const CommandResult own = causticd("render --scene " + lens + out);
  ASSERT_EQ(own.status, 0) << own.output;
  EXPECT_NE(own.output.find("light grid 128^2"), std::string::npos) << own.output;
  // Calibrated again where auto, with the calibration there, takes 64^2: the
  // grids measured still run up to the scene's own (each rebuild of the
  // gallery's calibrations once measured fewer).
  const CommandResult again =
      causticd("calibrate --scene " + lens + " --photons 200000 --max-side 64 --frames 1 --set render.accuracy_target=0.2");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("light grid 64^2"), std::string::npos) << again.output;
  grids.clear();
  const auto recalibrated = nlohmann::json::parse(std::ifstream(dir_ / "biconvex.calibration.json"));
  for (const auto& e : recalibrated["entries"]) grids.insert(e["light_grid"].get<int>());
  EXPECT_EQ(grids, (std::set<int>{64, 128})) << again.output;
}

TEST_F(Cli, CalibrateWritesWhatRenderThenUses) {
  // A copy of the lens scene in the test folder, so the calibration lands beside it.
  nlohmann::json j = nlohmann::json::parse(std::ifstream(scene("lens")));
  j["mesh"] = (fs::path(CAUSTIC_ASSET_DIR) / "meshes" / "lens.obj").string();
  std::ofstream(dir_ / "lens.json") << j.dump();
  const std::string lens = (dir_ / "lens.json").string();
  const CommandResult c = causticd("calibrate --scene " + lens + " --photons 200000 --max-side 64 --frames 1");
  ASSERT_EQ(c.status, 0) << c.output;
  EXPECT_NE(c.output.find("auto at target 0.05"), std::string::npos) << c.output;
  const auto cal = nlohmann::json::parse(std::ifstream(dir_ / "lens.calibration.json"));
  EXPECT_EQ(cal["entries"].size(), 12u);  // 6 levels (as loaded, 8^2 .. 128^2) x Fresnel on/off; directional light
  const CommandResult r = causticd("render --scene " + lens + " -o " + (dir_ / "l.png").string() + " --width 64 --height 64");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("fidelity: auto"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("expected relative L1"), std::string::npos) << r.output;
  // Moving the light takes the scene away from its calibration: the full model, uncalibrated.
  const CommandResult moved = causticd("render --scene " + lens + " -o " + (dir_ / "l.png").string() +
                                       " --width 64 --height 64 --set light.direction=[0.1,0,-1]");
  EXPECT_NE(moved.output.find("mesh as loaded"), std::string::npos) << moved.output;
  EXPECT_NE(moved.output.find("not calibrated"), std::string::npos) << moved.output;
  EXPECT_NE(moved.output.find("lens.calibration.json was made for other physics"), std::string::npos) << moved.output;
  EXPECT_EQ(r.output.find("was made for other physics"), std::string::npos) << r.output;

  expect_rejected("calibrate --scene " + lens + " --max-side 10", "--max-side");
  expect_rejected("calibrate --scene " + lens + " --set render.accuracy_target=0", "render.accuracy_target");
  expect_rejected("render --scene " + lens + " -o " + (dir_ / "l.png").string() + " --set render.mesh_resolution=1",
                  "render.mesh_resolution");
  std::ofstream(dir_ / "lens.calibration.json") << R"({"format": "causticd-calibration-1", "entries": 3})";
  expect_rejected("render --scene " + lens + " -o " + (dir_ / "l.png").string(), "lens.calibration.json");
}

TEST_F(Cli, PrintsItsVersion) {
  const CommandResult r = causticd("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("causticd"), std::string::npos);
}
