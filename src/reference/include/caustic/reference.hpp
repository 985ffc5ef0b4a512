// SPDX-License-Identifier: LGPL-2.1-or-later
// The reference renderer: an independent CPU photon tracer on the exact
// geometry (the caustic face with interpolated normals, through Embree, and
// the flat face as a plane). It shares only the scene loader and the optics
// formulas with the rest of the project, so it can catch the GL engine's
// mistakes. Output is relative irradiance on the same screen rectangle.
#pragma once

#include "caustic/image.hpp"
#include "caustic/mesh.hpp"

#include <cstdint>
#include <functional>

namespace caustic {

struct ReferenceOptions {
  std::uint64_t photons = 1'000'000;  ///< rounded up to a square number of strata
  std::uint64_t seed = 1;             ///< same seed, same image, whatever the thread count
  int threads = 0;                    ///< 0: one per hardware thread, and never more
  std::function<void(double done)> progress;  ///< 0..1, from the calling thread
};

struct ReferenceResult {
  HdrImage image;                   ///< relative irradiance, render.width x render.height (spectral: luminance)
  RgbHdrImage rgb;                  ///< a spectral scene's or tinted face's colour; empty for a grey one
  int wavelengths = 1;              ///< wavelengths traced
  std::uint64_t photons = 0;        ///< launched
  std::uint64_t photons_on_screen = 0;
  double seconds = 0;
};

/// Traces `options.photons` photons, stratified over the light's footprint
/// on the object, through the object to the screen; a spectral scene
/// shares them among its render.wavelengths, each with its own index, and
/// adds them in colour as the engine does; a tinted face (Mesh::colours)
/// filters each photon by its colour where the photon crosses the face,
/// interpolated there (the engine takes each triangle's mean). Throws
/// SceneError for a scene
/// the renderer cannot represent (as the engine does).
ReferenceResult trace_reference(const Scene& scene, const Mesh& mesh, const ReferenceOptions& options);

}  // namespace caustic
