// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd calibrate`: measures every configuration fidelity "auto" may
// choose for one scene against the reference tracer and writes the result
// beside the scene file (S.json -> S.calibration.json), where `render`,
// `serve` and the gallery find it.
#include "commands.hpp"

#include "caustic/calibrate.hpp"
#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/spectral.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace caustic::app {
namespace {

struct CalibrateCommandOptions {
  std::filesystem::path scene, output;
  std::vector<std::string> assignments;
  CalibrateOptions calibrate;
};

int run_calibrate(const CalibrateCommandOptions& opt) {
  Scene scene;
  SceneLevels levels;
  if (!load_scene_levels("calibrate", opt.scene, opt.assignments, &scene, &levels)) return bad_input;
  // The grids measured run up to the scene's own, not to the one the last
  // calibration let auto choose (each rebuild would measure fewer).
  scene.render.light_grid = levels.written_light_grid;
  const std::filesystem::path output = opt.output.empty() ? calibration_path(opt.scene) : opt.output;
  if (!output_writable("calibrate", output, "--output", scene_inputs(opt.scene, scene))) return bad_input;
  // The reference is traced first (on every core), then kept beside each
  // frame: refused before minutes of measuring as render and reference
  // refuse them (peak RSS at 4096 px a side: 0.75 GB grey, 2.1 in colour).
  const auto [w, h] = calibration_size(scene, opt.calibrate);
  const bool tint = tinted(*levels.levels.source), colour = spectral(scene) || tint;
  const int threads = reference_threads(0);
  const std::uint64_t kept = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * (colour ? 24 : 12);
  if (!memory_suffices("calibrate", "--max-side " + std::to_string(opt.calibrate.max_side),
                       std::string("a ") + (colour ? "colour" : "grey") + " frame of " + std::to_string(w) + "x" +
                           std::to_string(h) + " and its reference on " + std::to_string(threads) + " thread" +
                           (threads == 1 ? "" : "s"),
                       std::max(frame_bytes(w, h, colour) + kept, reference_bytes(w, h, colour, tint, threads)),
                       "give a smaller --max-side"))
    return bad_input;
  // Made all the same (the scene may turn to "auto" later), but it is not what renders now.
  if (scene.render.fidelity == Fidelity::manual)
    std::cerr << "causticd calibrate: warning: render.fidelity is \"manual\": the scene renders as written and "
                 "reads no calibration until it is \"auto\"\n";
  return run_reporting("calibrate", opt.scene, [&] {
    GlContext context(egl_platform_from_environment());
    Engine engine;
    CalibrateOptions options = opt.calibrate;
    options.progress = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
    std::printf("calibrating %s at %dx%d on %s: %zu levels, reference %llu photons\n", opt.scene.string().c_str(), w,
                h, context.renderer().c_str(), levels.levels.resolutions().size(),
                static_cast<unsigned long long>(options.photons));
    const Calibration c = calibrate(scene, levels.levels, engine, context.renderer(), options);
    // Readers never see half a file, and a failed write leaves none.
    write_text_files({{output, calibration_to_json(c).dump(2) + "\n"}});
    const FidelityChoice choice = choose_fidelity(c, scene.render.accuracy_target, levels.levels, light_grid_bound(scene));
    const std::string grid = choice.config.light_grid > 0
                                 ? ", light grid " + std::to_string(choice.config.light_grid) + "^2"
                                 : "";
    std::printf("auto at target %.3g: mesh %d, point model %s, Fresnel %s%s, expected L1 %.4f%s\n",
                scene.render.accuracy_target, choice.config.mesh_resolution,
                point_model_name(choice.config.point_model),
                choice.config.fresnel ? "on" : "off", grid.c_str(), choice.expected_l1.value_or(0),
                choice.meets_target ? "" : " (nothing met the target: the most accurate)");
    std::printf("wrote %s\n", output.string().c_str());
  });
}

}  // namespace

std::function<int()> add_calibrate_command(CLI::App& app) {
  auto opt = std::make_shared<CalibrateCommandOptions>();
  CLI::App* cmd = app.add_subcommand("calibrate", "Measure each fidelity configuration of a scene against the reference");
  cmd->add_option("--scene", opt->scene, "Scene file (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--output,-o", opt->output, "Calibration file (default: beside the scene, S.calibration.json)")
      ->check(not_empty());
  cmd->add_option("--set", opt->assignments, "Override a scene key before calibrating");
  cmd->add_option("--photons", opt->calibrate.photons, "Photons for the reference")
      ->transform(decimal())
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1} << 36));
  cmd->add_option("--seed", opt->calibrate.seed, "Random seed of the reference")
      ->transform(decimal())
      ->check(seed_number());
  cmd->add_option("--max-side", opt->calibrate.max_side, "Render size of the longer side")
      ->transform(decimal())
      ->check(CLI::Range(64, 4096));
  cmd->add_option("--frames", opt->calibrate.frames, "Timed frames per configuration")
      ->transform(decimal())
      ->check(CLI::Range(1, 50));
  return [cmd, opt] { return cmd->parsed() ? run_calibrate(*opt) : -1; };
}

}  // namespace caustic::app
