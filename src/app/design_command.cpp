// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd design`: from a target picture to the freeform face, its scene,
// optionally the millable solid, a JSON report and a side-by-side picture.
// Every output is written under a temporary name and renamed only once all
// of them are complete, so a failure leaves nothing half-written.
#include "commands.hpp"

#ifdef CAUSTICD_WITH_DESIGN
#include "caustic/design.hpp"
#include "caustic/design_colour.hpp"
#include "caustic/design_solid.hpp"
#include "caustic/design_verify.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/image_io.hpp"
#include "caustic/shown_text.hpp"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>
#endif

#include <iostream>

namespace caustic::app {

#ifdef CAUSTICD_WITH_DESIGN
namespace {

struct DesignCommandOptions {
  std::filesystem::path target, face, scene, solid, report, side_by_side;
  std::optional<std::string> name, description;
  design::DesignOptions design;
  bool force = false, verify = false, no_check = false, regular = false, colour = false, accept_unconverged = false;
  std::uint64_t photons = 4'000'000;
};

const char* kCommand = "causticd design: ";

int bad(const std::string& message) {
  std::cerr << kCommand << message << "\n";
  return bad_input;
}

// A text for the scene file: the scene parser's length limit (bytes), and
// valid UTF-8 without control characters, since it is shown in the gallery
// as it is. Returns what is wrong, or an empty string.
std::string text_problem(const std::string& text, std::size_t max_len, bool may_be_empty) {
  if (text.empty() && !may_be_empty) return "must not be empty";
  if (text.size() > max_len) return "is longer than " + std::to_string(max_len) + " bytes";
  if (holds_control_characters(text)) return "must not contain control characters";
  try {
    (void)nlohmann::json(text).dump();
  } catch (const nlohmann::json::exception&) {
    return "must be valid UTF-8";
  }
  return "";
}

// Flags checked before any work; the message names the flag.
int check_flags(DesignCommandOptions& o) {
  // Limits as in the scene parser (scene-format.md): name 200, description 2000.
  if (o.name)
    if (const auto problem = text_problem(*o.name, 200, false); !problem.empty()) return bad("--name: " + problem);
  if (o.description)
    if (const auto problem = text_problem(*o.description, 2000, true); !problem.empty())
      return bad("--description: " + problem);
  const auto& d = o.design;
  // A floor far below any glass geometric optics describes (10 um, some 20
  // wavelengths of light): at 1e-300 mm the face's single floats were all 0.
  if (!(std::isfinite(d.size) && d.size >= 0.01 && d.size <= 1e4)) return bad("--size: must be in [0.01, 10000] mm");
  if (!(std::isfinite(d.focus) && d.focus >= 0.01 && d.focus <= 1e6)) return bad("--focus: must be in [0.01, 1e6] mm");
  if (!(std::isfinite(d.ior) && d.ior > 1 && d.ior <= 4)) return bad("--ior: must be in (1, 4]");
  if (d.resolution < 16 || d.resolution > 2048)
    return bad("--resolution: must be in [16, 1024] (up to 2048 with --force), got " + std::to_string(d.resolution));
  if (d.resolution > 1024 && !o.force)
    return bad("--resolution: " + std::to_string(d.resolution) + " needs --force (above 1024 the solve takes minutes)");
  if (o.force && d.resolution <= 1024)
    std::cerr << "causticd design: warning: --force: has no effect at --resolution " << d.resolution
              << " (it allows more than 1024)\n";
  if (!(std::isfinite(d.black_floor) && d.black_floor >= 1e-6 && d.black_floor < 1))
    return bad("--black-floor: must be in [1e-6, 1)");
  if (!(std::isfinite(d.min_thickness) && d.min_thickness >= 0 && d.min_thickness <= 1e4))
    return bad("--min-thickness: must be in [0, 10000] mm");
  if (o.face.extension() != ".obj") return bad("--output " + o.face.string() + ": the face file must end in .obj");
  if (o.scene.empty()) o.scene = std::filesystem::path(o.face).replace_extension(".json");
  if (o.scene.extension() != ".json") return bad("--scene-out " + o.scene.string() + ": must end in .json");
  if (!o.solid.empty() && o.solid.extension() != ".obj") return bad("--solid " + o.solid.string() + ": must end in .obj");
  if (!o.side_by_side.empty() && o.side_by_side.extension() != ".png")
    return bad("--side-by-side " + o.side_by_side.string() + ": must end in .png");
  if (o.no_check && (o.verify || !o.side_by_side.empty()))
    return bad("--no-check: cannot be combined with --verify or --side-by-side");
  // Each file once: two outputs at one path would leave the second's
  // content under the first's name.
  const std::pair<const char*, const std::filesystem::path*> outputs[] = {
      {"--output", &o.face}, {"--scene-out", &o.scene}, {"--solid", &o.solid},
      {"--report", &o.report}, {"--side-by-side", &o.side_by_side}};
  const auto same = [](const std::filesystem::path& a, const std::filesystem::path& b) {
    return std::filesystem::absolute(a).lexically_normal() == std::filesystem::absolute(b).lexically_normal();
  };
  for (std::size_t i = 0; i < std::size(outputs); ++i) {
    const auto& [flag, p] = outputs[i];
    if (p->empty()) continue;
    // Tried now, not found after a solve of minutes.
    if (!output_writable("design", *p, flag, {o.target})) return bad_input;
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].second->empty() && same(*outputs[j].second, *p))
        return bad(std::string(flag) + " " + p->string() + ": the same file as " + outputs[j].first);
  }
  return ok;
}

// What `render` would refuse of the designed scene and face (d.face),
// refused before a file is written: the same checks, in memory. A face
// whose relief reaches the screen is the likely case (a wide lens, a short
// throw).
void check_renders(const Scene& scene, const design::Design& d, double focus) {
  const Mesh& face = d.face;
  try {
    validate_mesh(face);
    validate_scene(scene);
    check_geometry(scene, face, place_object(scene.object, face));
  } catch (const SceneError& e) {
    std::string why = std::string("the designed glass would not render (") + e.what() + ")";
    if (e.key() == "screen.center") {
      char hint[160];
      std::snprintf(hint, sizeof hint, ": the screen, --focus %g mm away, lies within the glass (relief %.1f mm); lengthen "
                    "--focus or shrink --size", focus, d.report.relief);
      why += hint;
    }
    throw SceneError("", why);
  }
}

// Grey panels as colour ones (R = G = B).
RgbHdrImage as_rgb(const HdrImage& grey) {
  RgbHdrImage out;
  for (int c = 0; c < 3; ++c) set_channel(out, c, grey);
  return out;
}

// Halves (box filter) an RGB panel `factor` times over, channel by channel.
RgbHdrImage box_down(const RgbHdrImage& image, int factor) {
  RgbHdrImage out;
  for (int c = 0; c < 3; ++c) set_channel(out, c, caustic::box_down(channel(image, c), factor));
  return out;
}

// Target | engine render [| reference render], tone-mapped alike per
// channel (a colour design's panels are in colour); halved (box filter)
// down to at most 256 pixels a side so the picture stays small enough to
// share.
Rgba8Image side_by_side(std::vector<RgbHdrImage> panels, double exposure) {
  int factor = 1;
  while (panels[0].width / factor > 256 && panels[0].width % (2 * factor) == 0) factor *= 2;
  if (factor > 1)
    for (auto& p : panels) p = box_down(p, factor);
  const int w = panels[0].width, h = panels[0].height, gap = 4, count = static_cast<int>(panels.size());
  Rgba8Image out{count * w + (count - 1) * gap, h,
                 std::vector<std::uint8_t>(std::size_t(count * w + (count - 1) * gap) * h * 4, 255)};
  for (int k = 0; k < count; ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        std::uint8_t* px = &out.pixels[(std::size_t(y) * out.width + k * (w + gap) + x) * 4];
        for (int c = 0; c < 3; ++c) {
          const float e = panels[k].pixels[3 * (std::size_t(y) * w + x) + c];
          const double v = std::pow(1 - std::exp(-exposure * std::max(0.0f, e)), 1 / 2.2);
          px[c] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(v, 0.0, 1.0)));
        }
      }
  return out;
}

nlohmann::json verification_json(const design::Verification& v) {
  return {{"seconds", v.seconds}, {"ssim", v.ssim}, {"relative_l1", v.relative_l1}, {"leak", v.leak},
          {"target_leak", v.ideal_leak}, {"landed", v.landed}};
}

void print_verification(const char* who, const design::Verification& v) {
  std::printf("%s: SSIM %.4f, relative L1 %.2f%%, light on black %.3f%% (target %.3f%%), landed %.4f, %.2f s\n", who,
              v.ssim, 100 * v.relative_l1, 100 * v.leak, 100 * v.ideal_leak, v.landed, v.seconds);
}

int run_design(DesignCommandOptions o) {
  if (const int status = check_flags(o); status != ok) return status;
  design::Image target;
  RgbHdrImage colour_target;  // --colour: the picture in RGB; the face is shaped for its brightest channel
  std::vector<std::string> warnings;
  try {
    if (o.colour) colour_target = design::load_target_rgb(o.target, &warnings);
    target = o.colour ? design::brightest_channel(colour_target) : design::load_target(o.target, &warnings);
  } catch (const design::TargetError& e) {
    return bad(std::string("--target ") + e.what());
  }
  for (const std::string& w : warnings) std::cerr << "causticd design: warning: --target " << w << "\n";
  o.design.resample = o.regular;
  const bool bar = isatty(STDERR_FILENO);
  design::ProgressFn progress;
  if (bar)
    progress = [last = -1.0](const design::Progress& p) mutable {
      if (p.seconds - last < 0.1) return;
      last = p.seconds;
      std::fprintf(stderr, "\rtransport: contrast step %d/%d, iteration %d, residual %.2e, %.1f s   ", p.step,
                   p.steps, p.iteration, p.residual, p.seconds);
      std::fflush(stderr);
    };
  return run_reporting("design", o.target, [&] {
    design::Design d;
    try {
      d = design::design_face(target, o.design, progress);
    } catch (const design::TargetError& e) {
      throw SceneError("", e.what());
    } catch (const std::invalid_argument& e) {
      throw SceneError("", std::string("--") + e.what());
    }
    if (bar) std::fprintf(stderr, "\n");
    if (o.colour) design::tint_face(d, colour_target);
    const auto& r = d.report;
    nlohmann::json report = {
        {"target", o.target.string()}, {"resolution", d.n}, {"size_mm", o.design.size}, {"focus_mm", o.design.focus},
        {"ior", o.design.ior}, {"black_floor", o.design.black_floor}, {"design_seconds", r.seconds},
        {"transport_residual", r.transport_residual}, {"converged", r.converged}, {"iterations", r.iterations},
        {"snell_passes", r.snell_passes}, {"snell_settled", r.snell_settled},
        {"tir_vertices", r.tir_vertices}, {"max_slope_deg", r.max_slope_deg}, {"relief_mm", r.relief},
        {"min_thickness_mm", r.min_thickness}, {"resampled", o.design.resample}, {"colour", o.colour}};
    const auto scene_dir = std::filesystem::absolute(o.scene).parent_path();
    const auto mesh_rel = std::filesystem::absolute(o.face).lexically_normal().lexically_relative(scene_dir.lexically_normal());
    Scene scene = design::design_scene(d, mesh_rel.generic_string(), std::clamp(d.n, 256, 1024));
    if (o.name) scene.name = *o.name;
    if (o.description) scene.description = *o.description;
    check_renders(scene, d, o.design.focus);
    // A face the solve did not settle on puts light where the picture has
    // none: said, and not written unless asked for (after the checks of
    // what the user asked for, which name the flag to change).
    if (const std::string why = design::convergence_failure(d.report); !why.empty()) {
      if (!o.accept_unconverged)
        throw std::runtime_error("the design is not written: " + why +
                                 " (a higher --black-floor or a softer picture helps; --accept-unconverged writes it "
                                 "anyway)");
      std::cerr << "causticd design: warning: --accept-unconverged: writing a design that did not converge: " << why
                << "\n";
    }
    std::optional<design::Verification> engine, reference;
    std::optional<design::ColourVerification> colour;
    if (!o.no_check) {
      GlContext context(egl_platform_from_environment());
      // A colour design's one render gives both the shape's figures and the colours'.
      if (o.colour) colour = design::verify_colour_with_engine(d, colour_target);
      engine = colour ? colour->brightest : design::verify_with_engine(d);
      report["engine"] = verification_json(*engine);
      if (colour)
        report["engine"]["colour"] = {{"relative_l1_rgb", colour->relative_l1}, {"chromaticity_error", colour->chromaticity_error}};
    }
    if (o.verify) {
      reference = design::verify_with_reference(d, o.photons);
      report["reference"] = verification_json(*reference);
      report["reference"]["photons"] = o.photons;
    }
    report["seconds_total"] = r.seconds + (engine ? engine->seconds : 0.0);
    // All or none of the outputs (write_complete): each under a hidden name
    // first, renamed once every one is complete.
    std::vector<std::filesystem::path> outputs;
    for (const auto* p : {&o.face, &o.scene, &o.solid, &o.side_by_side, &o.report})
      if (!p->empty()) outputs.push_back(*p);
    write_complete(outputs, [&](const std::filesystem::path& out, const std::filesystem::path& to) {
      if (out == o.face) {
        write_obj(d.face, to);
      } else if (out == o.scene) {
        write_text(to, scene_to_json(scene).dump(2) + "\n");
      } else if (out == o.solid) {
        design::write_solid_obj(design::solid_mesh(d.grid, r.flat_offset), to);
      } else if (out == o.side_by_side) {
        const double exposure = design::target_exposure(design::target_irradiance(d));
        std::vector<RgbHdrImage> panels;
        if (colour) {
          panels = {colour->aim, colour->render};
        } else {
          panels = {as_rgb(design::target_irradiance(d)), as_rgb(engine->render)};
        }
        // The reference's check is of the shape (the brightest channel of a colour design).
        if (reference) panels.push_back(as_rgb(reference->render));
        write_png(side_by_side(std::move(panels), exposure), to);
      } else {
        write_text(to, report.dump(2) + "\n");
      }
    });

    std::printf("design: %d^2 cells in %.2f s (transport %d iterations, residual %.1e; %d Snell pass%s)\n", d.n,
                r.seconds, r.iterations, r.transport_residual, r.snell_passes, r.snell_passes == 1 ? "" : "es");
    std::printf("face: relief %.3f mm, max slope %.1f deg, %d TIR vertices, thinnest glass %.2f mm, flat face at z = %.3f mm\n",
                r.relief, r.max_slope_deg, r.tir_vertices, r.min_thickness, r.flat_offset);
    if (engine) print_verification(o.colour ? "engine (brightest channel)" : "engine", *engine);
    if (colour)
      std::printf("colour: relative L1 R %.2f%%, G %.2f%%, B %.2f%%; chromaticity error %.4f (luminance-weighted mean)\n",
                  100 * colour->relative_l1[0], 100 * colour->relative_l1[1], 100 * colour->relative_l1[2],
                  colour->chromaticity_error);
    if (reference) print_verification("reference", *reference);
    std::printf("wrote %s, %s", o.face.string().c_str(), o.scene.string().c_str());
    for (const auto* p : {&o.solid, &o.report, &o.side_by_side})
      if (!p->empty()) std::printf(", %s", p->string().c_str());
    std::printf("\n");
  }, bar ? "\n" : "");
}

}  // namespace
#endif

std::function<int()> add_design_command(CLI::App& app) {
#ifdef CAUSTICD_WITH_DESIGN
  auto opt = std::make_shared<DesignCommandOptions>();
  CLI::App* cmd = app.add_subcommand("design", "Design the freeform face that projects a target picture");
  cmd->add_option("--target", opt->target, "Target picture (PNG, JPEG, EXR, TIFF, ...)")->required();
  cmd->add_option("--output,-o", opt->face, "Freeform face to write (.obj, millimetres, vertex normals)")->required();
  cmd->add_option("--scene-out", opt->scene, "Scene file to write (.json; default: beside the face)")->check(not_empty());
  cmd->add_option("--name", opt->name, "Scene name shown in the gallery (default: \"Designed caustic\")");
  cmd->add_option("--description", opt->description, "Scene description shown in the gallery");
  cmd->add_option("--size", opt->design.size, "Lens side, mm")->check(decimal_real());
  cmd->add_option("--focus", opt->design.focus, "Screen distance below the face, mm")->check(decimal_real());
  cmd->add_option("--ior", opt->design.ior, "Index of refraction (1.49: PMMA)")->check(decimal_real());
  cmd->add_option("--resolution", opt->design.resolution, "Cells per side (16..1024; 2048 with --force)")
      ->transform(decimal());
  cmd->add_flag("--force", opt->force, "Allow resolutions above 1024");
  cmd->add_option("--black-floor", opt->design.black_floor, "Darkest density, relative to the brightest")
      ->check(decimal_real());
  cmd->add_flag("--accept-unconverged", opt->accept_unconverged,
                "Write a design whose transport or Snell passes did not converge (exit 1 otherwise)");
  cmd->add_option("--min-thickness", opt->design.min_thickness, "Thinnest glass, mm")->check(decimal_real());
  cmd->add_option("--solid", opt->solid, "Also write the watertight slab (.obj) for milling")->check(not_empty());
  CLI::Option* verify = cmd->add_flag("--verify", opt->verify, "Also trace the design with the reference photon tracer");
  cmd->add_option("--photons", opt->photons, "Photons for --verify")
      ->transform(decimal())
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1} << 34))
      ->needs(verify);
  cmd->add_option("--side-by-side", opt->side_by_side, "PNG: target | engine render (| reference render with --verify)")->check(not_empty());
  cmd->add_option("--report", opt->report, "JSON file with every figure")->check(not_empty());
  cmd->add_flag("--no-check", opt->no_check, "Skip the engine render (no OpenGL needed)");
  cmd->add_flag("--regular-grid", opt->regular, "Resample the face onto a regular lens grid (no sliver triangles)");
  cmd->add_flag("--colour", opt->colour,
                "Design in colour: shape the face for the brightest channel and tint its vertices (docs/design.md)");
  return [cmd, opt] { return cmd->parsed() ? run_design(*opt) : -1; };
#else
  CLI::App* cmd = app.add_subcommand("design", "Design a freeform face (not built in)");
  cmd->allow_extras();
  return [cmd] {
    if (!cmd->parsed()) return -1;
    std::cerr << "causticd design: design is not built in (configure with -DCAUSTICD_WITH_DESIGN=ON)\n";
    return static_cast<int>(bad_input);
  };
#endif
}

}  // namespace caustic::app
