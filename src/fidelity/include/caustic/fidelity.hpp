// SPDX-License-Identifier: LGPL-2.1-or-later
// render.fidelity "auto": from a calibration (each cheaper configuration's
// measured error against the reference tracer on one scene), choose the
// cheapest configuration that meets the scene's accuracy target.
//
// Cost order, cheapest first: fewer mesh vertices (the caustic pass is
// linear in triangles), then for a solid fewer light-grid rays (the
// multipass method is linear in them), then the approximate point-light
// entry (the exact one solves for the entry point per vertex), then
// Fresnel off. Measured
// times are kept in the calibration for people; the order does not depend
// on them, so the same calibration gives the same choice on every machine.
#pragma once

#include "caustic/mesh_levels.hpp"
#include "caustic/scene.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace caustic {

/// What "auto" may change: the rest of the scene is the physics.
struct FidelityConfig {
  int mesh_resolution = 0;  ///< as render.mesh_resolution
  PointModel point_model = PointModel::exact;
  bool fresnel = true;
  int light_grid = 0;       ///< a solid's render.light_grid; 0 for a slab (and: keep the scene's)
  bool operator==(const FidelityConfig&) const = default;
};

struct CalibrationEntry {
  FidelityConfig config;
  std::size_t vertices = 0;    ///< of the mesh level
  double relative_l1 = 0;      ///< against the reference (full physics)
  double relative_rmse = 0;
  double ssim = 1;
  double ray_ms = 0;           ///< median caustic pass where it was calibrated
  /// Against the full model rendered by the engine at the streamed size
  /// (Calibration::streamed_width x height), with no box filter: what a
  /// visitor sees, facets included. Absent in calibrations made before
  /// they were measured.
  std::optional<double> streamed_l1;
  std::optional<double> streamed_ssim;  ///< of the tone-mapped pictures
};

/// Whether `e` meets `target`: relative L1 against the reference, and where
/// measured, relative L1 and 1 - SSIM against the full model at the
/// streamed size. The worst of these is its error.
bool meets_target(const CalibrationEntry& e, double target);
double worst_error(const CalibrationEntry& e);

struct Calibration {
  std::string fingerprint;  ///< scene_fingerprint of what was calibrated
  std::uint64_t reference_photons = 0;
  int width = 0, height = 0;  ///< render size of the calibration
  int compare_factor = 1;     ///< box filter before comparing
  int streamed_width = 0, streamed_height = 0;  ///< where streamed_* were measured; 0 when not
  std::string renderer;       ///< GL_RENDERER where ray_ms was measured
  std::vector<CalibrationEntry> entries;
};

/// "exact" or "approximate", as the scene format and calibrations spell it.
const char* point_model_name(PointModel model);

/// Identifies what a calibration is valid for: the object, light position or
/// direction, screen and intensity mode, and the mesh; not the settings
/// "auto" chooses, the render size or post-processing.
std::string scene_fingerprint(const Scene& scene, const Mesh& mesh);

nlohmann::json calibration_to_json(const Calibration& calibration);
/// Throws SceneError (key inside the file) on a malformed calibration.
Calibration calibration_from_json(const nlohmann::json& j);
/// A calibration file's bound: the build writes a few KiB.
inline constexpr std::size_t kMaxCalibrationFileBytes = std::size_t{1} << 20;
/// The calibration for `fingerprint` in `file`, or none when the file is
/// missing or calibrates something else. Throws SceneError when it is
/// malformed or larger than kMaxCalibrationFileBytes.
std::optional<Calibration> load_calibration(const std::filesystem::path& file, const std::string& fingerprint);

struct FidelityChoice {
  FidelityConfig config;
  std::optional<double> expected_l1;  ///< from the calibration; none when uncalibrated
  bool meets_target = false;          ///< false: nothing calibrated met it, the most accurate was taken
};

/// The cheapest calibrated configuration that meets the target
/// (meets_target) among the levels `levels` offers; when none does, the one
/// with the smallest worst_error. Without a calibration: the full model (mesh as loaded, exact, Fresnel).
/// `light_grid`: a solid scene's own light grid; calibrated grids above it
/// are never chosen (0: no bound, a slab).
FidelityChoice choose_fidelity(const std::optional<Calibration>& calibration, double target, const MeshLevels& levels,
                               int light_grid = 0);

/// choose_fidelity()'s `light_grid` for `scene`: a solid's own grid, 0 for
/// anything else (its configurations have no grid).
int light_grid_bound(const Scene& scene);

/// The keys "auto" decides (section, key): a value written for one of them
/// is overridden while render.fidelity is "auto", and its writer is told so.
/// render.light_grid only for a solid: a slab has no light grid.
inline constexpr const char* kFidelityAutoKeys[][2] = {
    {"render", "mesh_resolution"}, {"light", "point_model"}, {"render", "fresnel"}, {"render", "light_grid"}};

/// The light grids a solid's calibration tries, up to the scene's own.
inline constexpr int kCalibratedLightGrids[] = {64, 128, 256};

/// For each of kFidelityAutoKeys that `written` (a scene document or a
/// patch) sets while `scene` renders with fidelity "auto": (key, message).
std::vector<std::pair<std::string, std::string>> fidelity_overrides(const nlohmann::json& written, const Scene& scene);

/// Every key that `written` sets but another setting of `scene` overrides
/// or leaves unused: fidelity_overrides, follow_overrides,
/// spectral_overrides, shape_overrides and setting_overrides in turn. What
/// the server warns about for a scene file or a patch, and the command line
/// for a scene it renders.
std::vector<std::pair<std::string, std::string>> scene_overrides(const nlohmann::json& written, const Scene& scene);

/// `scene` with the choice written into mesh_resolution, point_model,
/// fresnel and (a solid's, when chosen) light_grid when its fidelity is
/// "auto"; unchanged when "manual".
Scene resolve_fidelity(Scene scene, const FidelityChoice& choice);

/// The fidelity block of GET .../params: mode, target, what is rendered and
/// its expected error, and whether the calibration covers the parameters now.
nlohmann::json describe_fidelity(const Scene& scene, const Mesh& source, const MeshLevels& levels,
                                 const std::optional<Calibration>& calibration);

/// The calibration file of a scene file: S.json -> S.calibration.json.
std::filesystem::path calibration_path(const std::filesystem::path& scene_file);

/// What to say when `scene_file`'s calibration is there but load_calibration()
/// found it made for other physics (a changed scene or mesh, other
/// parameters, an older fingerprint): "" when there is none to speak of.
std::string stale_calibration_note(const std::filesystem::path& scene_file, const std::optional<Calibration>& loaded);

}  // namespace caustic
