// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic engine: renders a scene's relative irradiance on the screen
// rectangle with one ray per caustic-face vertex (docs/physics.md), or for a
// solid one ray per light-grid point traced through all its faces on the
// CPU (§12), then bloom and tone mapping. Needs a current OpenGL 4.5 core context (GlContext
// or one that a host such as GStreamer provides) on the calling thread, and
// must be used and destroyed on that thread.
#pragma once

#include "caustic/image.hpp"
#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace caustic {

class EngineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a read-back delivers the picture.
enum class PixelFormat { rgba, i420 };

/// Where the caustic pass follows the rays, sets up each triangle and
/// deposits its exact coverage: in the GL's vertex, geometry and fragment
/// stages, or on the CPU with the GL adding the image (the same picture).
/// automatic: the CPU under a software renderer, whose geometry stage runs
/// on one thread and whose fragment stage pays for every triangle's box.
/// A grey frame deposited on the CPU is post-processed there too (the same
/// picture, within a level of 255) unless its tone map is local.
enum class TriangleSetup { automatic, gpu, cpu };

/// What the last render did.
struct FrameStats {
  double ray_ms = 0;          ///< caustic pass, GPU work finished
  double trace_ms = 0;        ///< of ray_ms, rays traced, triangles set up and deposited on the CPU
  bool cpu_setup = false;     ///< the caustic pass set up and deposited its triangles on the CPU
  double post_ms = 0;         ///< bloom and tone mapping, GPU work finished
  bool cpu_post = false;      ///< post-processing ran on the CPU (a grey frame the CPU deposited)
  // Triangle counts are the last ray pass's (of a spectral frame: its reddest wavelength).
  std::uint32_t drawn = 0;    ///< triangles that reached the screen
  std::uint32_t dropped = 0;  ///< triangles with a vertex lost to TIR, a miss or grazing incidence
  std::uint32_t folded = 0;   ///< drawn triangles whose screen orientation is the minority one
  std::uint32_t collapsed = 0; ///< drawn triangles of (nearly) zero screen area: flux into one pixel
  std::uint32_t split = 0;    ///< a solid's light-grid triangles whose corners took different paths
  double exposure = 1;        ///< the exposure the tone map used
  double metered = 0;         ///< "auto": the metered quantile of the lit pixels (0: none lit)
  int wavelengths = 1;        ///< ray passes of the last frame: its wavelength samples (1: monochrome)
  bool colour = false;        ///< the frame is RGB (dispersive glass or a tinted face): read_hdr_rgb() holds it
};

class Engine {
 public:
  Engine();
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Sets what to render. Checks the geometry (check_geometry) and throws
  /// SceneError without changing anything when the model cannot represent it.
  /// Marks the frame dirty only when something changed. `moved`: the mesh
  /// is the last one's next state (water's next step), so automatic
  /// exposure eases on instead of starting afresh as for a new object.
  /// `placed_by`: the bounds that place the object (MeshLevels::bounds, the
  /// loaded mesh's), so a coarser level sits exactly where the loaded mesh
  /// does, inside the box the public checks judge; by default, and when
  /// they were taken about another flat-face normal, the mesh's own.
  void set_scene(const Scene& scene, std::shared_ptr<const Mesh> mesh, bool moved = false,
                 const std::shared_ptr<const MeshBounds>& placed_by = nullptr);

  /// A cheaper frame for interaction: the caustic drawn at 1/divisor of the
  /// output size per side, no bloom, bilinearly upsampled by the tone map
  /// into the full-size picture (read_hdr then returns the small image).
  /// 1 (the default) is full quality. Marks the frame dirty when it changes.
  void set_preview_divisor(int divisor);

  /// The picture is left standing (progressive fidelity's last step): full
  /// frames of a spectral scene sample render.still_wavelengths rather than
  /// render.wavelengths, where that is more; previews are unaffected. Off by
  /// default. Marks the frame dirty when that changes the wavelengths drawn.
  void set_still(bool still);

  /// Where the caustic pass sets up its triangles (automatic by default).
  /// Marks the frame dirty when it changes.
  void set_triangle_setup(TriangleSetup setup);

  /// True when the next render() will draw.
  bool dirty() const;

  /// Renders if the scene changed since the last render (only post-processing
  /// when only `post` changed). Returns whether anything was drawn. With
  /// automatic exposure the frame stays dirty while the shown exposure eases
  /// towards the metered one (post.exposure_adapt_s), then settles.
  bool render();

  /// The relative irradiance: of a spectral frame, its luminance.
  HdrImage read_hdr() const;
  /// Linear sRGB, white-balanced to the light (grey for a monochrome frame).
  RgbHdrImage read_hdr_rgb() const;
  Rgba8Image read_ldr() const;

  /// Streaming read-back without waiting for the GPU: queue a copy of the
  /// current tone-mapped picture tagged `tag` (e.g. its parameter version),
  /// as RGBA or converted on the GPU to I420 (BT.601 limited range, planes
  /// Y, U, V packed without padding; width a multiple of 8, height even)...
  void start_readback(std::uint64_t tag, PixelFormat format = PixelFormat::rgba);
  /// ...and copy the newest finished one into `dest` (`bytes` long: the
  /// picture's size in its format), if any (waits when `wait`).
  bool poll_readback(std::uint8_t* dest, std::size_t bytes, std::uint64_t* tag, bool wait);
  /// The same into an image (RGBA pictures).
  bool poll_ldr_readback(Rgba8Image* picture, std::uint64_t* tag, bool wait);
  /// Bytes of a picture of this engine's size in `format`.
  std::size_t picture_bytes(PixelFormat format) const;
  const FrameStats& stats() const;
  /// Number of caustic passes drawn so far.
  std::uint64_t ray_passes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustic
