// SPDX-License-Identifier: LGPL-2.1-or-later
#include "commands.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_io.hpp"
#include "caustic/spectral.hpp"


#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <tuple>

namespace caustic::app {
namespace {

struct RenderOptions {
  std::filesystem::path scene;
  std::vector<std::filesystem::path> outputs;
  std::vector<std::string> assignments;
  int width = 0;
  int height = 0;
  int frames = 1;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Refused with the size as the user set it, rather than left to fail an
// allocation midway or to the OOM killer: 8192 x 8192 in colour takes 6 GB.
bool frame_fits(const RenderOptions& opt, const Scene& scene, const Mesh& mesh) {
  const bool colour = spectral(scene) || tinted(mesh);
  const int w = scene.render.width, h = scene.render.height;
  const std::string named = (opt.width ? "--width " : "render.width ") + std::to_string(w) +
                            (opt.height ? " --height " : " render.height ") + std::to_string(h);
  const std::string what = std::string("a ") + (colour ? "colour" : "grey") + " frame of " + std::to_string(w) + "x" +
                           std::to_string(h);
  return memory_suffices("render", named, what, frame_bytes(w, h, colour));
}

int run_render(const RenderOptions& opt) {
  Scene scene;
  SceneLevels levels;
  // --width and --height are assignments after every --set; their
  // warnings name the flag, which is what the user wrote.
  std::vector<std::string> assignments = opt.assignments, flags(opt.assignments.size());
  for (const auto& [flag, key, value] : {std::tuple{"--width", "render.width", opt.width},
                                         std::tuple{"--height", "render.height", opt.height}})
    if (value) {
      assignments.push_back(std::string(key) + "=" + std::to_string(value));
      flags.push_back(std::string(flag) + " " + std::to_string(value));
    }
  for (std::size_t i = 0; i < opt.outputs.size(); ++i) {
    const auto& out = opt.outputs[i];
    const auto ext = out.extension().string();
    if (ext != ".exr" && ext != ".png") {
      std::cerr << "causticd render: --output " << out.string() << ": the file must end in .exr or .png\n";
      return bad_input;
    }
    // One file written twice keeps only the second: a slip in the command.
    const auto where = [](const std::filesystem::path& p) {
      std::error_code ec;
      const auto resolved = std::filesystem::weakly_canonical(p, ec);
      return ec ? std::filesystem::absolute(p, ec).lexically_normal() : resolved;
    };
    for (std::size_t j = 0; j < i; ++j)
      if (where(opt.outputs[j]) == where(out)) {
        std::cerr << "causticd render: --output " << out.string() << ": the same file as --output "
                  << opt.outputs[j].string() << "\n";
        return bad_input;
      }
  }
  if (!load_scene_levels("render", opt.scene, assignments, &scene, &levels, flags)) return bad_input;
  for (const auto& out : opt.outputs)
    if (!output_writable("render", out, "--output", scene_inputs(opt.scene, scene))) return bad_input;
  const auto mesh = levels.levels.at(scene.render.mesh_resolution);
  if (!frame_fits(opt, scene, *mesh)) return bad_input;
  return run_reporting("render", opt.scene, [&] {
    GlContext context(egl_platform_from_environment());
    Engine engine;
    const auto& placed_by = levels.levels.bounds;
    engine.set_scene(scene, mesh, false, placed_by);
    std::vector<double> ray_ms, post_ms;
    for (int i = 0; i < opt.frames; ++i) {
      // Re-setting an unchanged scene would not render again: changing the
      // mesh handle forces a full frame for the timing loop.
      if (i > 0) engine.set_scene(scene, std::make_shared<const Mesh>(*mesh), false, placed_by);
      engine.render();
      ray_ms.push_back(engine.stats().ray_ms);
      post_ms.push_back(engine.stats().post_ms);
    }
    const auto& st = engine.stats();
    std::printf("renderer: %s\n", context.renderer().c_str());
    std::printf("%s\n", describe_choice(scene, levels).c_str());
    std::printf("mesh: %zu vertices, %zu triangles; target %dx%d\n", mesh->positions.size(), mesh->triangles.size(),
                scene.render.width, scene.render.height);
    std::printf("triangles: %u drawn, %u dropped, %u folded, %u collapsed\n", st.drawn, st.dropped, st.folded,
                st.collapsed);
    std::printf("render time: %.2f ms caustic + %.2f ms post (median of %d frame%s)\n", median(ray_ms),
                median(post_ms), opt.frames, opt.frames == 1 ? "" : "s");
    if (st.wavelengths > 1) std::printf("spectral: %d wavelengths, one caustic pass each\n", st.wavelengths);
    write_complete(opt.outputs, [&](const std::filesystem::path& out, const std::filesystem::path& to) {
      // A colour frame (dispersive or tinted) keeps R, G, B channels; a grey one, Y.
      if (out.extension() == ".exr" && st.colour) write_exr(engine.read_hdr_rgb(), to);
      else if (out.extension() == ".exr") write_exr(engine.read_hdr(), to);
      else write_png(engine.read_ldr(), to);
    });
    for (const auto& out : opt.outputs) std::printf("wrote %s\n", out.string().c_str());
  });
}

}  // namespace

std::function<int()> add_render_command(CLI::App& app) {
  auto opt = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render one scene to EXR (HDR relative irradiance) and/or PNG");
  cmd->add_option("--scene", opt->scene, "Scene file (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--output,-o", opt->outputs, "Output file(s): .exr (HDR, before post) or .png (tone-mapped)")
      ->required();
  cmd->add_option("--set", opt->assignments, "Override a scene key, e.g. --set light.direction=[0,0.2,-1]");
  cmd->add_option("--width", opt->width, "Render width in pixels")
      ->transform(decimal())
      ->check(CLI::Range(16, 8192));
  cmd->add_option("--height", opt->height, "Render height in pixels")
      ->transform(decimal())
      ->check(CLI::Range(16, 8192));
  cmd->add_option("--frames", opt->frames, "Render this many frames and print the median time")
      ->transform(decimal())
      ->check(CLI::Range(1, 1000));
  return [cmd, opt] { return cmd->parsed() ? run_render(*opt) : -1; };
}

}  // namespace caustic::app
