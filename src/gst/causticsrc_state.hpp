// SPDX-License-Identifier: LGPL-2.1-or-later
// What a causticsrc instance holds, shared by the element (causticsrc.cpp)
// and the C++ functions that reach into it (causticsrc_api.cpp): settings
// under a lock, streaming state owned by the streaming thread.
#pragma once

#include "caustic/gst/causticsrc.hpp"
#include "due_wait.hpp"
#include "frame_worker.hpp"

#include <gst/base/gstpushsrc.h>
#include <gst/video/video.h>

#include <atomic>
#include <mutex>
#include <string>

namespace caustic::gst {

struct State {
  std::mutex lock;  // guards the properties and the source hand-over
  std::string scene_path;
  int width = 0, height = 0;  // 0: the scene's render size
  int fps_n = 30, fps_d = 1;
  GstClockTime still_interval = 0;  // re-send an unchanged picture this often; 0: every frame
  std::atomic<bool> early_frames{true};  // a change after a still spell leaves when drawn (causticsrc_pacing.cpp)
  std::shared_ptr<caustic::ParamStore> params;
  std::shared_ptr<const caustic::MeshLevels> meshes;
  std::shared_ptr<caustic::water::Pool> pool;  // the stream's water: source.pool, for other threads
  bool from_file = false;  // params and meshes were loaded from scene_path, not given by set_source()
  std::function<void()> on_overrun;  // set before streaming
  // Streaming thread only (the worker owns `source` while it runs):
  caustic::gst::FrameSource source;
  std::unique_ptr<caustic::gst::FrameWorker> worker;
  GstVideoInfo info;
  std::atomic<GstClockTime> frame_duration{0};  // of info's rate, for queries from any thread; 0: no caps yet
  guint64 frame_index = 0;
  std::uint64_t overruns_told = 0, renders_logged = 0;
  std::atomic<std::uint64_t> overruns{0};  // read from any thread
  std::atomic<std::int64_t> heartbeat{0};  // the render thread's, read from any thread
  GstClockTime first_due = 0;  // running time of frame first_index: the grid's start
  guint64 first_index = 0;      // frame 0, or the last frame that left early
  // The picture last pushed, held so that its address stays its own: the
  // worker hands back the very same buffer while nothing changed.
  GstBuffer* last_sent = nullptr;
  GstClockTime last_sent_due = 0;
  std::atomic<bool> send_next{false};         // a key frame was asked for: send even if unchanged
  std::atomic<bool> flushing{false};          // unlock() to unlock_stop(): no wait for a picture
  std::atomic<std::uint64_t> skipped{0};      // unchanged frames not sent (still-interval-ms), any thread
  caustic::gst::DueWait due_wait;
};

/// Waits for the next frame to send and takes its picture, a reference
/// (causticsrc_pacing.cpp): GST_FLOW_OK with *picture and *due (its running
/// time) set, or the flow that ended the wait. Streaming thread.
GstFlowReturn next_frame(State& s, GstElement* element, GstBuffer** picture, GstClockTime* due);

/// New caps (causticsrc_pacing.cpp): while streaming, a change of format,
/// size or rate replaces the worker and restarts the grid after the last
/// frame sent. Streaming thread.
void renegotiate(State& s, const GstVideoInfo& next);

/// Gives the stream its water as it starts (causticsrc_api.cpp). Under s.lock.
void start_water(State& s);

/// The element's properties (causticsrc_props.cpp): GObject's set_property
/// and get_property, and their installation in the class.
void set_property(GObject* object, guint id, const GValue* value, GParamSpec* pspec);
void get_property(GObject* object, guint id, GValue* value, GParamSpec* pspec);
void install_properties(GObjectClass* gobject);

/// The GEnum of the water-solver property: WaterSolver's values, by the
/// nicks "auto", "cpu" and "gl" (causticsrc_api.cpp).
GType water_solver_type();

}  // namespace caustic::gst

struct GstCausticSrc {
  GstPushSrc parent;
  caustic::gst::State* state;
};
struct GstCausticSrcClass {
  GstPushSrcClass parent_class;
};

GType gst_caustic_src_get_type();
