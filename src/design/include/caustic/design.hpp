// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic designer: from a target picture to the freeform face of a
// refractive slab (flat face toward a collimated light at normal incidence)
// that throws that picture on a parallel screen at the focus distance.
// Method: grid optimal transport (Nader and Guennebaud 2018), closed-form
// paraxial heights, then exact-Snell normal integration; docs/design.md.
//
// Conventions: millimetres; lens footprint [-W/2, W/2]^2 centred on the
// origin, the flat face on top (outward normal +z), light travelling -z, the
// screen the same W x W square at z = -focus below the mean level (z = 0) of
// the freeform face. Grid indices (i, j) run along +x and +y; target images
// have their row 0 at the top (+y), as every picture of the project.
#pragma once

#include "caustic/design_target.hpp"
#include "caustic/mesh.hpp"

#include <functional>
#include <string>
#include <vector>

namespace caustic::design {

struct DesignOptions {
  double size = 100.0;          ///< lens side W, mm
  double focus = 200.0;         ///< screen distance below the face's mean level, mm
  double ior = 1.49;            ///< PMMA
  int resolution = 512;         ///< N: cells per side (the face has (N+1)^2 vertices)
  double black_floor = 1e-2;    ///< density floor eps, relative to the brightest cell
  double min_thickness = 2.0;   ///< thinnest glass between flat and freeform face, mm
  int homotopy_steps = 6;       ///< contrast steps rho^t, t = 1/steps ... 1
  double tolerance = 1e-4;      ///< stop the transport when sum |residual| falls below
  int max_iterations = 400;     ///< per homotopy step
  double height_tolerance = 1e-3;  ///< exact-Snell passes stop at this largest change, mm
  int max_snell_passes = 4;
  /// Face on a regular lens grid (no sliver triangles) instead of the warped
  /// transport grid. Off by default: measured, it blurs sharp edges (more
  /// light on black pixels, higher error) while the warped grid with its
  /// explicit normals renders the target closely (docs/design.md).
  bool resample = false;
};

/// A (w x w)-vertex grid on the lens with the screen point each vertex must
/// send its ray to. Row-major, j along +y; millimetres.
struct FaceGrid {
  int w = 0;
  std::vector<glm::dvec2> lens;    ///< vertex position (x, y)
  std::vector<glm::dvec2> screen;  ///< where its ray must land on the screen
  std::vector<double> height;      ///< z of the vertex
  std::vector<glm::dvec2> slope;   ///< required dh/dx, dh/dy (exact Snell)
  int tir = 0;                     ///< vertices whose slope was capped short of total internal reflection
};

/// Called now and then during the transport solve.
struct Progress {
  int step = 0, steps = 0;   ///< homotopy step (1-based) and count
  int iteration = 0;         ///< total iterations so far
  double residual = 0;       ///< sum |area - mass| of the current step
  double seconds = 0;        ///< since the start of the design
};
using ProgressFn = std::function<void(const Progress&)>;

/// The largest transport residual of a design taken as converged. The
/// residual sum |area - mass| is the share of the light the map sends to
/// the wrong cells, the relative L1 of the designed irradiance against the
/// target: allowed the 5% the project holds a render to (render.
/// accuracy_target's default, docs/accuracy.md). The stall stop leaves
/// 10^-4 to 3 * 10^-3 on ordinary pictures (docs/design.md).
inline constexpr double kMaxTransportResidual = 0.05;

/// Figures of the designed face (no rendering involved).
struct FaceReport {
  double transport_residual = 0;  ///< final sum |area - mass| (1 = the whole lens)
  int iterations = 0;
  /// transport_residual <= kMaxTransportResidual: the transport (stopped at
  /// its tolerance, a stall or its iteration cap) reached the picture.
  bool converged = false;
  int snell_passes = 0;
  /// The exact-Snell passes stopped because the heights settled (last
  /// change below height_tolerance), not at max_snell_passes.
  bool snell_settled = false;
  double snell_change = 0;        ///< largest height change of the last pass, mm
  int tir_vertices = 0;           ///< vertices whose required normal asks for total internal reflection
  double max_slope_deg = 0;       ///< largest angle of a face normal from +z
  double relief = 0;              ///< max - min height of the freeform face, mm
  double min_thickness = 0;       ///< flat face minus highest freeform point, mm
  double flat_offset = 0;         ///< z of the flat face, mm
  double seconds = 0;
};

struct Design {
  DesignOptions options;
  int n = 0;                       ///< cells per side
  std::vector<double> mass;        ///< n x n target masses, row j along +y, sum 1
  double floor_mass = 0;           ///< mass of a cell at the black floor
  std::vector<glm::dvec2> warped;  ///< (n+1)^2 lens points of the transport map, unit square
  FaceGrid grid;                   ///< the face's vertices, heights and slopes (double precision)
  Mesh face;                       ///< freeform face, mm, explicit vertex normals
  FaceReport report;
};

/// Why a design cannot be trusted, in plain words ("" when it can): the
/// transport not converged or the exact-Snell passes not settled.
std::string convergence_failure(const FaceReport& report);

/// Designs the face for `target` (linear luminance, any size; resampled to
/// options.resolution cells). Throws std::invalid_argument for options out of
/// range (the message names the option) and TargetError for an all-black target.
Design design_face(const Image& target, const DesignOptions& options, const ProgressFn& progress = {});

/// The target as the screen should receive it: relative irradiance (mean 1
/// over the screen), options.resolution pixels per side, row 0 at the top.
HdrImage target_irradiance(const Design& design);

}  // namespace caustic::design
