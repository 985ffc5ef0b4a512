// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/design.hpp"

#include "face.hpp"
#include "heights.hpp"
#include "transport.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace caustic::design {
namespace {

void require(bool ok, const char* option, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(option) + ": " + what);
}

void check_options(const DesignOptions& o) {
  const auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
  require(finite_positive(o.size) && o.size <= 1e4, "size", "must be a lens side in (0, 10000] mm");
  require(finite_positive(o.focus) && o.focus <= 1e6, "focus", "must be a distance in (0, 1e6] mm");
  require(std::isfinite(o.ior) && o.ior > 1.0 && o.ior <= 4.0, "ior", "must be in (1, 4]");
  require(o.resolution >= 4 && o.resolution <= 2048, "resolution", "must be in [4, 2048]");
  require(std::isfinite(o.black_floor) && o.black_floor >= 1e-6 && o.black_floor < 1, "black-floor",
          "must be in [1e-6, 1)");
  require(std::isfinite(o.min_thickness) && o.min_thickness >= 0 && o.min_thickness <= 1e4, "min-thickness",
          "must be in [0, 10000] mm");
  // Upper bounds well beyond any use (6 steps, 400 iterations and 4 passes
  // by default): what lies past them is a design that never ends.
  require(o.homotopy_steps >= 1 && o.homotopy_steps <= 100, "homotopy-steps", "must be in [1, 100]");
  require(o.max_iterations >= 1 && o.max_iterations <= 100000, "max-iterations", "must be in [1, 100000]");
  require(o.max_snell_passes >= 1 && o.max_snell_passes <= 100, "max-snell-passes", "must be in [1, 100]");
  require(std::isfinite(o.tolerance) && o.tolerance > 0, "tolerance", "must be positive");
  require(std::isfinite(o.height_tolerance) && o.height_tolerance > 0, "height-tolerance", "must be positive (mm)");
}

}  // namespace

Design design_face(const Image& target, const DesignOptions& options, const ProgressFn& progress) {
  check_options(options);
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (target.width <= 0 || target.height <= 0) throw TargetError("the target picture is empty");
  const int n = options.resolution;
  Design d;
  d.options = options;
  d.n = n;

  // A NaN would be skipped by max_element below and turn every density NaN
  // (a flat face), an infinity would read as "all black": both are refused
  // by name. The cells are weighted means, so finite pixels give finite cells.
  if (target.pixels.size() != std::size_t(target.width) * target.height)
    throw TargetError("the target picture's pixels do not fill its " + std::to_string(target.width) + "x" +
                      std::to_string(target.height) + " size");
  for (std::size_t p = 0; p < target.pixels.size(); ++p)
    if (!std::isfinite(target.pixels[p]))
      throw TargetError("the target picture's pixel (" + std::to_string(p % target.width) + ", " +
                        std::to_string(p / target.width) + ") is " + (std::isnan(target.pixels[p]) ? "NaN" : "infinite"));
  // Cell densities rho = max(I / max I, eps); image row 0 is the top (+y).
  const Image cells = box_resample_square(target, n);
  const float brightest = *std::max_element(cells.pixels.begin(), cells.pixels.end());
  if (!(brightest > 0)) throw TargetError("the target picture is all black");
  d.mass.resize(std::size_t(n) * n);
  double sum = 0;
  for (int row = 0; row < n; ++row)
    for (int i = 0; i < n; ++i)
      sum += d.mass[std::size_t(n - 1 - row) * n + i] = std::max(double(cells.at(i, row)) / brightest, options.black_floor);
  for (double& m : d.mass) m /= sum;
  d.floor_mass = options.black_floor / sum;

  TransportOptions topt;
  topt.steps = options.homotopy_steps;
  topt.tolerance = options.tolerance;
  topt.max_iterations = options.max_iterations;
  ProgressFn timed;
  if (progress) timed = [&](const Progress& p) { Progress q = p; q.seconds = seconds(); progress(q); };
  TransportResult map = solve_transport(n, d.mass, topt, timed);
  d.warped = map.lens;
  d.report.transport_residual = map.residual;
  d.report.iterations = map.iterations;

  // The warped grid: lens point X_v sends its light to the regular screen point x_v.
  const int w = n + 1;
  const double size = options.size;
  std::vector<glm::dvec2> screen_unit(std::size_t(w) * w);
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) screen_unit[std::size_t(j) * w + i] = glm::dvec2(i, j) / double(n);
  FaceGrid grid;
  grid.w = w;
  grid.height = paraxial_heights(map.lens, screen_unit, vertex_mean(n, map.psi), size, options.focus, options.ior);
  for (std::size_t v = 0; v < screen_unit.size(); ++v) {
    grid.lens.push_back(size * (map.lens[v] - 0.5));
    grid.screen.push_back(size * (screen_unit[v] - 0.5));
  }
  if (options.resample) grid = resample_regular(grid, size);
  d.report.converged = map.residual <= kMaxTransportResidual;
  const SnellPasses snell =
      refine_heights(grid, options.focus, options.ior, options.height_tolerance, options.max_snell_passes);
  d.report.snell_passes = snell.passes;
  d.report.snell_settled = snell.settled;
  d.report.snell_change = snell.last_change;

  const auto [lo, hi] = std::minmax_element(grid.height.begin(), grid.height.end());
  d.report.relief = *hi - *lo;
  d.report.min_thickness = options.min_thickness;
  d.report.flat_offset = *hi + options.min_thickness;
  d.report.tir_vertices = grid.tir;
  double max_slope = 0;
  for (const auto& g : grid.slope) max_slope = std::max(max_slope, glm::length(g));
  d.report.max_slope_deg = std::atan(max_slope) * 180.0 / std::acos(-1.0);
  d.face = face_mesh(grid);
  d.grid = std::move(grid);
  d.report.seconds = seconds();
  return d;
}

std::string convergence_failure(const FaceReport& r) {
  char text[320];
  if (!r.converged) {
    std::snprintf(text, sizeof text,
                  "the transport did not converge: %.1f%% of the light still goes to the wrong place after %d "
                  "iterations (at most %.0f%%)",
                  100 * r.transport_residual, r.iterations, 100 * kMaxTransportResidual);
    return text;
  }
  if (!r.snell_settled) {
    std::snprintf(text, sizeof text,
                  "the face's heights did not settle: the last of %d exact-Snell passes still moved them by %.3g mm",
                  r.snell_passes, r.snell_change);
    return text;
  }
  return "";
}

HdrImage target_irradiance(const Design& design) {
  const int n = design.n;
  HdrImage out{n, n, std::vector<float>(std::size_t(n) * n)};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      out.pixels[std::size_t(n - 1 - j) * n + i] = static_cast<float>(design.mass[std::size_t(j) * n + i] * n * n);
  return out;
}

}  // namespace caustic::design
