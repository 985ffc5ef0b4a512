// SPDX-License-Identifier: LGPL-2.1-or-later
#include "commands.hpp"

#include "caustic/image_io.hpp"
#include "caustic/reference.hpp"
#include "caustic/spectral.hpp"


#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace caustic::app {
namespace {

struct ReferenceCommandOptions {
  std::filesystem::path scene, output;
  std::vector<std::string> assignments;
  std::uint64_t photons = 10'000'000;
  std::uint64_t seed = 1;
  int threads = 0;
};

// Refused before the tracing, which keeps an image per thread.
bool image_fits(const ReferenceCommandOptions& opt, const Scene& scene, const Mesh& mesh) {
  const int threads = reference_threads(opt.threads);
  const bool colour = spectral(scene) || tinted(mesh);
  const int w = scene.render.width, h = scene.render.height;
  return memory_suffices("reference",
                         "render.width " + std::to_string(w) + " render.height " + std::to_string(h) + " on " +
                             std::to_string(threads) + " thread" + (threads == 1 ? "" : "s"),
                         std::string("a ") + (colour ? "colour" : "grey") + " image of " + std::to_string(w) + "x" +
                             std::to_string(h),
                         reference_bytes(w, h, colour, tinted(mesh), threads),
                         "give a smaller size or fewer --threads");
}

int run_reference(const ReferenceCommandOptions& opt) {
  Scene scene;
  Mesh mesh;
  if (!load_scene_and_mesh("reference", opt.scene, opt.assignments, &scene, &mesh)) return bad_input;
  if (opt.output.extension() != ".exr") {
    std::cerr << "causticd reference: --output " << opt.output.string() << ": the file must end in .exr\n";
    return bad_input;
  }
  if (!output_writable("reference", opt.output, "--output", scene_inputs(opt.scene, scene))) return bad_input;
  if (!image_fits(opt, scene, mesh)) return bad_input;
  // More threads than cores buy no speed for their images' memory: the
  // tracer takes the cores, and the flag that asked more is said.
  if (const int threads = reference_threads(opt.threads); opt.threads > threads)
    std::cerr << "causticd reference: warning: --threads " << opt.threads << ": this machine has " << threads
              << (threads == 1 ? " core; 1 thread traces\n" : " cores; as many threads trace\n");
  ReferenceOptions options;
  options.photons = opt.photons;
  options.seed = opt.seed;
  options.threads = opt.threads;
  options.progress = [](double done) {
    const int width = 40, filled = static_cast<int>(done * width);
    std::fprintf(stderr, "\r[%s%s] %3.0f%%", std::string(filled, '#').c_str(), std::string(width - filled, ' ').c_str(),
                 100 * done);
    std::fflush(stderr);
  };
  return run_reporting("reference", opt.scene, [&] {
    const ReferenceResult r = trace_reference(scene, mesh, options);
    std::fprintf(stderr, "\n");
    write_complete({opt.output}, [&](const std::filesystem::path&, const std::filesystem::path& to) {
      if (!r.rgb.pixels.empty())
        write_exr(r.rgb, to);
      else
        write_exr(r.image, to);
    });
    std::printf("photons: %llu traced, %llu on the screen, in %.2f s: %.2f M photons/s\n",
                static_cast<unsigned long long>(r.photons), static_cast<unsigned long long>(r.photons_on_screen),
                r.seconds, r.photons / r.seconds / 1e6);
    std::printf("wrote %s\n", opt.output.string().c_str());
  }, "\n");
}

}  // namespace

std::function<int()> add_reference_command(CLI::App& app) {
  auto opt = std::make_shared<ReferenceCommandOptions>();
  CLI::App* cmd = app.add_subcommand("reference", "Render a scene with the independent photon tracer (HDR EXR)");
  cmd->add_option("--scene", opt->scene, "Scene file (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--output,-o", opt->output, "Output .exr (relative irradiance)")->required();
  cmd->add_option("--photons", opt->photons, "Photons to trace")
      ->transform(decimal())
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40));
  cmd->add_option("--seed", opt->seed, "Random seed (same seed, same image)")
      ->transform(decimal())
      ->check(seed_number());
  cmd->add_option("--threads", opt->threads, "Worker threads (0: all cores; at most the cores)")
      ->transform(decimal())
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--set", opt->assignments, "Override a scene key, e.g. --set render.fresnel=false");
  return [cmd, opt] { return cmd->parsed() ? run_reference(*opt) : -1; };
}

}  // namespace caustic::app
