// SPDX-License-Identifier: LGPL-2.1-or-later
#include "frame_source.hpp"

#include "caustic/gst/frame_meta.hpp"
#include "caustic/spectral.hpp"
#include "caustic/wave_gl.hpp"

#include <cstring>
#include <optional>

GST_DEBUG_CATEGORY_EXTERN(caustic_src_debug);

namespace caustic::gst {

namespace {

// Read-backs on the way, remembered: more than the engine keeps.
constexpr std::size_t kInFlightKept = 8;

// The preview's mesh: the configured level when the scene's is finer.
std::shared_ptr<const Mesh> preview_mesh(const MeshLevels& meshes, const Scene& scene, int level) {
  auto full = meshes.at(scene.render.mesh_resolution);
  auto it = meshes.resampled.find(level);
  return it != meshes.resampled.end() && it->second->positions.size() < full->positions.size() ? it->second : full;
}

// Makes a context current for a scope.
struct Current {
  GlContext& context;
  explicit Current(GlContext& c) : context(c) { context.make_current(); }
  ~Current() { context.release_current(); }
  Current(const Current&) = delete;
  Current& operator=(const Current&) = delete;
};

// The water's pacing for the negotiated frame interval (made afresh when
// that changes: what was measured was against the old budget).
WaterPacing& water_pacing(FrameSource& source) {
  const auto& p = source.progressive;
  const double budget = p.water_budget * std::chrono::duration<double, std::milli>(source.frame_interval).count();
  if (source.water_pacing.budget_ms() != budget) source.water_pacing = WaterPacing(budget, p.water_retry, p.water_retry_max);
  return source.water_pacing;
}

// The context, made on first use (current only while drawing, so that
// stopping the element on another thread can free it).
void ensure_context(FrameSource& source) {
  if (source.context) return;
  source.context = std::make_unique<GlContext>(egl_platform_from_environment());
  source.engine = std::make_unique<Engine>();
  source.context->release_current();
}

// Whether the water is to step on the GL, as source.water_solver and the
// renderer say (no GL call: the context need not be current).
bool water_wants_gl(const FrameSource& source) {
  return !source.water_gl_failed &&
         (source.water_solver == WaterSolver::gl ||
          (source.water_solver == WaterSolver::automatic && !source.context->software()));
}

// Hands the water's steps to the GL, or takes them back; the context is
// current. A GL that cannot step it (no compute shaders) leaves it on the
// CPU for good.
void place_water(FrameSource& source, bool gl) {
  if (gl == source.water_on_gl) return;
  if (!gl) {
    source.pool->detach();
    source.water_on_gl = false;
    return;
  }
  try {
    source.pool->attach([](const water::WaveParams& params, const water::WaveState& state) {
      return std::make_unique<water::WaveSolverGl>(params, state);
    });
    source.water_on_gl = true;
    GST_CAT_INFO(caustic_src_debug, "the water steps on the GL (%s)", source.context->renderer().c_str());
  } catch (const std::exception& e) {
    source.water_gl_failed = true;
    GST_CAT_WARNING(caustic_src_debug, "the water steps on the CPU: the GL could not (%s)", e.what());
  }
}

}  // namespace

GstBuffer* produce_frame(FrameSource& source, const ParamStore& params, const MeshLevels& meshes, int width,
                         int height, bool wait) {
  const auto now = std::chrono::steady_clock::now();
  if (params.version() != source.seen) {
    // Post-processing alone is no motion: the engine redoes only the tone map.
    ParamStore::Snapshot snap = params.snapshot();
    Scene caustic = snap.scene, before = source.seen_scene;
    caustic.post = before.post = PostParams{};
    if (source.seen == 0 || caustic != before) {
      // A change long after the one before it is a click, not a drag: worth
      // its full frame at once. Both times are when the changes were made,
      // not when this thread, busy drawing, got round to noticing them (on a
      // loaded machine it notices one version in many, far apart).
      source.isolated = source.seen == 0 || snap.published - snap.previous >= source.progressive.lone;
      source.changed_at = snap.published;
    }
    source.seen = snap.version;
    source.seen_scene = std::move(snap.scene);
  }
  // Water moves with the clock, a frame interval at a time; a drop falls
  // at the next advance even while the water is paused.
  if (source.pool && source.seen_scene.water) {
    using Clock = std::chrono::steady_clock;
    if (source.water_clock == Clock::time_point{}) source.water_clock = now;
    // A frame of water starts when the stream asks for a frame (its due
    // time), so that it is drawn by the next one: advanced at this thread's
    // own look, a few milliseconds late and at its own phase, a frame would
    // miss its due time whenever the render ends near it. Without asks
    // (a pipeline not yet playing), every interval and a half of its own.
    const Clock::time_point asked{Clock::duration(source.asked.load())};
    const auto since = now - source.water_clock;
    const bool on_ask = asked > source.water_clock && asked - source.water_clock >= source.frame_interval / 2;
    if (on_ask || since >= source.frame_interval * 3 / 2 || !source.picture) {
      // Whole intervals without asks, so that the water keeps the frame rate.
      const auto step = on_ask ? asked - source.water_clock
                        : since < source.frame_interval
                            ? since
                            : source.frame_interval * (since / source.frame_interval);
      ensure_context(source);
      const bool gl = water_wants_gl(source);
      std::optional<Current> current;  // only for a stepper on the GL
      if (gl || source.water_on_gl) current.emplace(*source.context);
      place_water(source, gl);
      try {
        source.water_dirty =
            source.pool->advance(*source.seen_scene.water, std::chrono::duration<double>(step).count()) ||
            source.water_dirty;
      } catch (const SceneError& e) {
        GST_CAT_WARNING(caustic_src_debug, "water not advanced: %s", e.what());
      }
      source.water_clock += std::chrono::duration_cast<Clock::duration>(step);
    }
  }
  // The first picture is a full one; after that, recent changes mean
  // motion, and so does water whose full frames do not fit the interval.
  const bool moving = source.progressive.enabled && source.picture && !source.isolated &&
                      now - source.changed_at < source.progressive.settle;
  const bool water = source.pool && source.seen_scene.water;
  // Paused water stands still: drawn full once, it needs no previews.
  const bool water_too_slow = water && !source.seen_scene.water->paused && source.progressive.enabled &&
                              source.picture && !water_pacing(source).want_full(now);
  const std::uint32_t want = moving || water_too_slow ? preview : full_quality;
  // Automatic exposure easing towards a new metering redraws the tone map
  // each frame until it settles (the version stays the same). Moving water
  // eases with its next frame, at most an interval away: a tone map redrawn
  // between its frames would only take time from the frames and the encoder.
  const bool water_moves = water && !source.seen_scene.water->paused;
  const bool settling = source.engine && source.engine->dirty() && !water_moves;
  // Left standing, a spectral scene's full frame samples more wavelengths.
  const Scene& seen = source.seen_scene;
  const bool still = want == full_quality && source.progressive.enabled && source.picture && !water_moves &&
                     frame_wavelengths(seen, false, true) > frame_wavelengths(seen, false, false) &&
                     now - source.changed_at >= source.progressive.still;
  const bool changed = source.seen != source.rendered || want != source.rendered_level ||
                       still != source.rendered_still || settling || source.water_dirty;
  if (!changed && !source.readback_pending && source.picture) return gst_buffer_ref(source.picture);
  // A full frame of water still on its way out (its fence not yet
  // signalled) is shown before a preview takes its place: the read-back
  // hands over the newest finished picture, so a preview drawn now would
  // hide it, and a try of water too slow for its interval would cost its
  // overrun and never be seen. The preview comes with the next frame.
  const bool full_on_its_way = water && want == preview && source.readback_pending &&
                               !source.in_flight.empty() && source.in_flight.back().level == full_quality;
  // Nor is a full frame of water the stream has not asked for since it was
  // handed over: the stream takes the newest picture when it asks, so a
  // stream held up for a moment would never send the try (the next blind
  // one a minute later). The preview comes once the stream has asked.
  const std::chrono::steady_clock::time_point last_ask{std::chrono::steady_clock::duration(source.asked.load())};
  if (water && want == preview && !source.readback_pending && source.picture && last_ask < source.picture_at &&
      caustic_buffer_get_frame_meta(source.picture)->level == full_quality)
    return gst_buffer_ref(source.picture);
  ensure_context(source);
  const Current current(*source.context);

  if (changed && !full_on_its_way) {
    // The scene noticed above is the one to draw (one snapshot per version).
    Scene scene = source.seen_scene;
    scene.render.width = width;  // the negotiated caps decide the size
    scene.render.height = height;
    const std::uint64_t version = source.rendered = source.seen;
    source.rendered_level = want;
    source.rendered_still = still;
    try {
      const int divisor = want == preview ? source.progressive.divisor : 1;
      source.engine->set_preview_divisor(divisor);
      source.engine->set_still(still);
      // Water's surface is its own: a preview thins it as it shrinks the picture.
      source.engine->set_scene(scene,
                               water             ? source.pool->mesh(divisor)
                               : want == preview ? preview_mesh(meshes, scene, source.progressive.mesh)
                                                 : meshes.at(scene.render.mesh_resolution),
                               water, water ? nullptr : meshes.bounds);
      source.water_dirty = false;
      const std::uint64_t before = source.engine->ray_passes();
      source.engine->render();
      source.renders += source.engine->ray_passes() - before;
      if (water && source.engine->ray_passes() > before) {
        const double ms = source.engine->stats().ray_ms + source.engine->stats().post_ms;
        auto& pacing = water_pacing(source);
        if (want == full_quality)
          pacing.full_drawn(ms, now);
        else
          pacing.preview_drawn(ms);
        GST_CAT_DEBUG(caustic_src_debug, "water %s frame: %.1f ms (a full one predicted %.1f ms, budget %.1f ms)",
                      want == full_quality ? "full" : "preview", ms, pacing.predicted_full_ms(), pacing.budget_ms());
      }
      if (source.observer) source.observer(source.engine->stats(), version);
      const std::uint64_t tag = ++source.readbacks;
      source.in_flight.push_back({tag, version, water ? source.pool->step() : 0, want});
      if (source.in_flight.size() > kInFlightKept) source.in_flight.pop_front();
      source.engine->start_readback(tag, source.format);
      source.readback_pending = true;
    } catch (const SceneError& e) {
      // Keep showing the last good picture; the store's own checks make this rare.
      GST_CAT_WARNING(caustic_src_debug, "parameters version %" G_GUINT64_FORMAT " not rendered: %s", version,
                      e.what());
      if (!source.picture) throw;
    }
  }
  if (source.readback_pending) {
    // The picture goes from the pixel buffer object straight into the
    // GstBuffer: its only copy on the way out of GL.
    const std::size_t bytes = source.engine->picture_bytes(source.format);
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, bytes, nullptr);
    GstMapInfo map;
    gst_buffer_map(buffer, &map, GST_MAP_WRITE);
    std::uint64_t tag = 0;
    bool ready = false;
    try {
      ready = source.engine->poll_readback(map.data, bytes, &tag, wait || !source.picture || full_on_its_way);
    } catch (...) {
      gst_buffer_unmap(buffer, &map);
      gst_buffer_unref(buffer);
      throw;
    }
    gst_buffer_unmap(buffer, &map);
    if (!ready) {
      gst_buffer_unref(buffer);
      return source.picture ? gst_buffer_ref(source.picture) : nullptr;  // the first, its fence slow: none yet
    }
    FrameSource::InFlight shown{tag, source.rendered, 0, source.rendered_level};
    while (!source.in_flight.empty() && source.in_flight.front().tag <= tag) {
      if (source.in_flight.front().tag == tag) shown = source.in_flight.front();
      source.in_flight.pop_front();
    }
    const std::uint64_t version = shown.version;
    source.readback_pending = false;
    caustic_buffer_set_frame_meta(buffer, version, shown.level, shown.water_step);
    if (source.picture) gst_buffer_unref(source.picture);
    source.picture = buffer;
    source.picture_version = version;
  }
  return gst_buffer_ref(source.picture);
}

void answer_snapshots(FrameSource& source) {
  std::vector<SnapshotRequests::Done> pending;
  {
    std::lock_guard lock(source.snapshots->lock);
    pending.swap(source.snapshots->pending);
  }
  if (pending.empty()) return;
  if (!source.context || !source.engine || !source.picture) {
    for (const auto& done : pending) done(nullptr, nullptr, nullptr);
    return;
  }
  Rgba8Image ldr;
  HdrImage hdr;
  RgbHdrImage colour;
  {
    const Current current(*source.context);
    ldr = source.engine->read_ldr();
    // A colour frame is read back once; its luminance is the grey image.
    if (source.engine->stats().colour) {
      colour = source.engine->read_hdr_rgb();
      hdr = luminance(colour);
    } else {
      hdr = source.engine->read_hdr();
    }
  }
  for (const auto& done : pending) done(&ldr, &hdr, colour.pixels.empty() ? nullptr : &colour);
}

void release(FrameSource& source) {
  if (source.picture) gst_buffer_unref(source.picture);
  source.picture = nullptr;
  if (source.context) {
    source.context->make_current();
    // The pool outlives the element (a codec switch makes another): its
    // water comes back to the CPU before the context that stepped it goes.
    if (source.water_on_gl) source.pool->detach();
    source.water_on_gl = false;
    source.engine.reset();
    source.context->release_current();
    source.context.reset();
  }
  source.rendered = source.seen = 0;
  source.picture_version = 0;
  source.rendered_level = full_quality;
  source.readback_pending = false;
  source.in_flight.clear();
  source.water_clock = {};
  source.water_dirty = false;
  source.water_pacing = WaterPacing();
  source.water_gl_failed = false;
}

}  // namespace caustic::gst
