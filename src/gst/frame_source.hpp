// SPDX-License-Identifier: LGPL-2.1-or-later
// What causticsrc draws with: a GL context and an engine that live on the
// render thread (frame_worker.hpp), and the last picture, re-sent while
// nothing changes.
#pragma once

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/mesh_levels.hpp"
#include "caustic/param_store.hpp"
#include "caustic/pool.hpp"
#include "water_pacing.hpp"

#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace caustic::gst {

/// Progressive fidelity: while parameters keep changing, frames are cheap
/// previews; once they have been still for `settle`, one full frame. A lone
/// change (the first for `lone`) gets its full frame at once: a click, not a
/// drag. `lone` is generous because a loaded server answers a drag's
/// changes late, and previews are what keeps it from overloading.
struct Progressive {
  bool enabled = true;
  std::chrono::milliseconds settle{40};
  std::chrono::milliseconds lone{250};
  /// A spectral scene left standing for `still` after its last change is
  /// drawn once more at render.still_wavelengths (Engine::set_still): a
  /// slower frame, worth it only once a visitor has let go.
  std::chrono::milliseconds still{500};
  int divisor = 2;   ///< preview caustic at 1/divisor of the output size per side
  int mesh = 32;     ///< preview mesh level, when it is coarser than the scene's
  /// Water moves every frame, so it is never still: its frames are full
  /// ones while a full frame's render (caustic and post-processing) fits
  /// `water_budget` of the frame interval (the rest goes to the simulation
  /// step and the readback), previews while it does not, and full ones
  /// again when the previews predict they fit (WaterPacing). Blind tries:
  /// `water_retry` after the first miss, then every `water_retry_max`.
  double water_budget = 0.8;
  std::chrono::milliseconds water_retry{1000};
  std::chrono::milliseconds water_retry_max{60000};
};

/// Requests for the picture last rendered (a REST client's frame.png),
/// queued from any thread and answered on the render thread, which alone
/// may touch the GL context. `Done` gets null pointers when there is no
/// picture to give (not streaming, stopped).
struct SnapshotRequests {
  using Done = std::function<void(const Rgba8Image* ldr, const HdrImage* hdr, const RgbHdrImage* colour)>;
  std::mutex lock;
  std::vector<Done> pending;
};

/// Where a pool's water steps (caustic/pool.hpp's Stepper): on the GL when
/// the renderer is a GPU (a software renderer steps it faster on the CPU),
/// or as set.
enum class WaterSolver { automatic, cpu, gl };

/// Fidelity levels in CausticFrameMeta.level.
enum FrameLevel : std::uint32_t { full_quality = 0, preview = 1 };

struct FrameSource {
  Progressive progressive;
  PixelFormat format = PixelFormat::rgba;  // as negotiated; set before streaming
  std::unique_ptr<GlContext> context;
  std::unique_ptr<Engine> engine;
  GstBuffer* picture = nullptr;  // in `format`; its CausticFrameMeta says the version and level it shows
  std::uint64_t rendered = 0;    // version last drawn (its read-back may still be on the way)
  std::uint32_t rendered_level = full_quality;
  bool rendered_still = false;   // ... drawn as a picture left standing (Progressive::still)
  std::uint64_t seen = 0;        // newest version noticed (one snapshot each)
  Scene seen_scene;              // its scene: what the next render draws
  std::chrono::steady_clock::time_point changed_at;  // when the caustic last changed (not post-processing)
  bool isolated = true;          // that change came after a still spell: no preview for it
  bool readback_pending = false;
  /// When the worker last handed a new picture to the stream (on its
  /// thread, under its lock): an ask stamped later took it; one stamped
  /// earlier may have too, and then a preview waits for one more ask.
  std::chrono::steady_clock::time_point picture_at{};
  /// What each read-back on its way shows, by its tag (a render count).
  struct InFlight {
    std::uint64_t tag, version, water_step;
    std::uint32_t level;
  };
  std::deque<InFlight> in_flight;
  std::uint64_t readbacks = 0;
  /// A scene with water: its surface, advanced by the time between frames
  /// and drawn anew each time it moves. Set before streaming.
  std::shared_ptr<water::Pool> pool;
  std::chrono::nanoseconds frame_interval{std::chrono::nanoseconds(1'000'000'000) / 30};  // as negotiated
  std::chrono::steady_clock::time_point water_clock{};  // when the water last advanced
  /// When the stream last asked for a frame (steady-clock ticks; 0: never),
  /// from the streaming thread: the water moves on at these due times.
  std::atomic<std::chrono::steady_clock::rep> asked{0};
  bool water_dirty = false;                             // moved since last drawn
  WaterSolver water_solver = WaterSolver::automatic;    // set before streaming
  bool water_gl_failed = false;                         // the GL could not step it: the CPU does
  bool water_on_gl = false;                             // this source's context steps the pool's water
  WaterPacing water_pacing;
  std::atomic<std::uint64_t> renders{0};  // caustic passes so far (read from any thread)
  std::atomic<std::uint64_t> picture_version{0};  // version of the newest finished picture, any thread
  std::function<void(const FrameStats&, std::uint64_t)> observer;  // after each render
  const std::shared_ptr<SnapshotRequests> snapshots = std::make_shared<SnapshotRequests>();
};

/// A new reference to the frame to send now: renders when the ParamStore's
/// version moved on (a preview while changes keep coming, see Progressive)
/// or when a preview is to be replaced by the full frame, and queues the
/// picture's read-back; sends the newest picture whose read-back has
/// finished (waiting only for the very first).
/// Creates the GL context on first use. Throws on GL failures.
/// `wait`: wait for the read-back (a render thread can); otherwise only the
/// very first picture is waited for.
GstBuffer* produce_frame(FrameSource& source, const ParamStore& params, const MeshLevels& meshes, int width,
                         int height, bool wait = false);

/// Answers the queued snapshot requests with the engine's current picture
/// and HDR image (the render thread's, or any thread once streaming stopped).
void answer_snapshots(FrameSource& source);

/// Frees the picture, the engine and the context (any thread, once streaming stopped).
void release(FrameSource& source);

}  // namespace caustic::gst
