// The caustic engine: renders a scene's relative irradiance on the screen
// rectangle with one ray per caustic-face vertex (docs/physics.md), then
// bloom and tone mapping. Needs a current OpenGL 4.5 core context (GlContext
// or one that a host such as GStreamer provides) on the calling thread, and
// must be used and destroyed on that thread.
#pragma once

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

/// Relative irradiance, one float per pixel, row 0 at the top of the screen.
struct HdrImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Tone-mapped 8-bit RGBA, row 0 at the top.
struct Rgba8Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

/// What the last render did.
struct FrameStats {
  double ray_ms = 0;          ///< caustic pass, GPU work finished
  double post_ms = 0;         ///< bloom and tone mapping, GPU work finished
  std::uint32_t drawn = 0;    ///< triangles that reached the screen
  std::uint32_t dropped = 0;  ///< triangles with a vertex lost to TIR, a miss or grazing incidence
  std::uint32_t folded = 0;   ///< drawn triangles whose screen orientation is the minority one
  std::uint32_t collapsed = 0; ///< drawn triangles of (nearly) zero screen area: flux into one pixel
};

class Engine {
 public:
  Engine();
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Sets what to render. Checks the geometry (check_geometry) and throws
  /// SceneError without changing anything when the model cannot represent it.
  /// Marks the frame dirty only when something changed.
  void set_scene(const Scene& scene, std::shared_ptr<const Mesh> mesh);

  /// True when the next render() will draw.
  bool dirty() const;

  /// Renders if the scene changed since the last render (only post-processing
  /// when only `post` changed). Returns whether anything was drawn.
  bool render();

  HdrImage read_hdr() const;
  Rgba8Image read_ldr() const;

  /// Streaming read-back without waiting for the GPU: queue a copy of the
  /// current tone-mapped picture tagged `tag` (e.g. its parameter version)...
  void start_ldr_readback(std::uint64_t tag);
  /// ...and take the newest finished copy, if any (waits when `wait`).
  bool poll_ldr_readback(Rgba8Image* picture, std::uint64_t* tag, bool wait);
  const FrameStats& stats() const;
  /// Number of caustic passes drawn so far.
  std::uint64_t ray_passes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustic
