// SPDX-License-Identifier: LGPL-2.1-or-later
// Measures, for one scene, every configuration fidelity "auto" may choose:
// the engine's error against the reference tracer (full physics: Fresnel
// on, exact point-light entry, the mesh as loaded) and its frame time.
#pragma once

#include "caustic/fidelity.hpp"

#include <functional>

namespace caustic {

class Engine;

struct CalibrateOptions {
  std::uint64_t photons = 16'000'000;  ///< for the reference
  std::uint64_t seed = 1;
  int max_side = 512;      ///< render size of the longer side (the aspect is kept)
  int compare_factor = 4;  ///< box filter before comparing (reference noise)
  int frames = 3;          ///< timed frames per configuration (median)
  bool streamed = true;    ///< also against the full model at the scene's render size
  std::function<void(const std::string&)> progress;  ///< one line per step
};

/// Runs the reference once and the engine on every configuration. `engine`
/// must belong to the GL context current on this thread. Throws SceneError
/// for a scene neither renderer can represent.
Calibration calibrate(const Scene& scene, const MeshLevels& levels, Engine& engine, const std::string& renderer,
                      const CalibrateOptions& options);

/// The render size a calibration uses for `scene` (each side a multiple of
/// the compare factor).
std::pair<int, int> calibration_size(const Scene& scene, const CalibrateOptions& options);

}  // namespace caustic
