// SPDX-License-Identifier: LGPL-2.1-or-later
// Design jobs through the designer library (src/design): built only when
// CAUSTICD_WITH_DESIGN is on; design_backend_off.cpp stands in otherwise.
#include "design_files.hpp"
#include "design_jobs.hpp"

#include "caustic/design.hpp"
#include "caustic/design_colour.hpp"
#include "caustic/design_target.hpp"
#include "caustic/design_verify.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

namespace caustic::server {
namespace {

// The library's messages name the file and quote the image library, whose
// text may hold the state directory's path: a visitor gets the reason alone.
std::string visitor_reason(const std::string& what, const std::string& file) {
  std::string reason = what;
  if (reason.rfind(file + ": ", 0) == 0) reason.erase(0, file.size() + 2);
  if (const auto paren = reason.find(" ("); paren != std::string::npos) reason.erase(paren);
  return reason;
}

std::shared_ptr<const Mesh> run(const std::filesystem::path& target, const std::filesystem::path& folder, int resolution,
                                bool colour, const std::function<void(const DesignBackend::Progress&)>& progress) {
  // Both kept at the design's n x n cells, which is all the designer, the
  // tint and the check read (resampled again at n, a picture is unchanged):
  // the full-size picture, 16 bytes a pixel in colour, is freed before the
  // design's minutes instead of after them.
  design::Image picture;
  RgbHdrImage colours;  // in colour: the face is shaped for the brightest channel, then tinted
  std::vector<std::string> said;  // what the picture holds that is not designed (an animated PNG's frames)
  try {
    if (colour) {
      const RgbHdrImage full = design::load_target_rgb(target, &said);
      // The brightest channel of the full picture, as it was designed before.
      picture = design::box_resample_square(design::brightest_channel(full), resolution);
      colours = design::box_resample_square(full, resolution);
    } else {
      picture = design::box_resample_square(design::load_target(target, &said), resolution);
    }
  } catch (const design::TargetError& e) {
    throw DesignFailure(visitor_reason(e.what(), target.string()));
  }
  design::DesignOptions options;
  options.resolution = resolution;
  design::Design d;
  try {
    // The transport's contrast steps are most of the time: 0 to 80%.
    d = design::design_face(picture, options, [&](const design::Progress& p) {
      progress({0.8 * (std::max(0, p.step - 1) + 0.5) / std::max(1, p.steps), "designing"});
    });
  } catch (const design::TargetError& e) {
    throw DesignFailure(e.what());
  }
  // A design that did not converge throws a picture other than the one sent.
  if (const std::string why = design::convergence_failure(d.report); !why.empty())
    throw DesignFailure(why + "; a picture with less contrast, or more of it lit, can be designed");
  if (colour) design::tint_face(d, colours);
  progress({0.85, "checking"});
  nlohmann::json report = {{"resolution", d.n},
                           {"design_seconds", d.report.seconds},
                           {"transport_residual", d.report.transport_residual},
                           {"converged", d.report.converged},
                           {"snell_passes", d.report.snell_passes},
                           {"snell_settled", d.report.snell_settled},
                           {"tir_vertices", d.report.tir_vertices},
                           {"max_slope_deg", d.report.max_slope_deg},
                           {"relief_mm", d.report.relief},
                           {"min_thickness_mm", d.report.min_thickness},
                           {"warnings", nlohmann::json::array()}};
  // In the designer's words, with the picture's path (in the state
  // directory) taken out wherever it stands.
  for (std::string w : said) {
    if (w.rfind(target.string() + ": ", 0) == 0) w.erase(0, target.string().size() + 2);
    for (auto at = w.find(target.string()); at != std::string::npos; at = w.find(target.string(), at))
      w.replace(at, target.string().size(), "the picture");
    report["warnings"].push_back({{"key", "picture"}, {"detail", w}});
  }
  {
    GlContext context(egl_platform_from_environment());
    // A colour design's one render gives both the shape's figures and the colours'.
    std::optional<design::ColourVerification> tinted;
    if (colour) tinted = design::verify_colour_with_engine(d, colours);
    const design::Verification engine = tinted ? tinted->brightest : design::verify_with_engine(d);
    report["engine"] = {{"seconds", engine.seconds}, {"ssim", engine.ssim}, {"relative_l1", engine.relative_l1},
                        {"leak", engine.leak}, {"target_leak", engine.ideal_leak}};
    report["seconds_total"] = d.report.seconds + engine.seconds;
    if (tinted)
      report["engine"]["colour"] = {{"relative_l1_rgb", tinted->relative_l1},
                                    {"chromaticity_error", tinted->chromaticity_error}};
    context.release_current();
  }
  progress({0.95, "storing"});
  try {
    write_obj(d.face, folder / "face.obj");
  } catch (const std::runtime_error&) {
    // It fails only when a write does, and its message holds the path.
    const int error = errno;
    throw StorageError(error ? error : EIO, std::string("cannot write face.obj: ") + std::strerror(error ? error : EIO));
  }
  write_atomic(folder / "scene.json", scene_to_json(design::design_scene(d, "face.obj", std::clamp(d.n, 256, 1024))).dump(2));
  // Last: its presence says the design is complete.
  write_atomic(folder / "report.json", report.dump(2));
  return std::make_shared<const Mesh>(std::move(d.face));
}

}  // namespace

DesignBackend design_backend() { return {run, true, static_cast<std::uint32_t>(design::kMaxTargetSide)}; }

}  // namespace caustic::server
