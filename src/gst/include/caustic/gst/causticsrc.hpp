// SPDX-License-Identifier: LGPL-2.1-or-later
// The `causticsrc` GStreamer element: a live source of rendered caustics.
// See causticsrc.cpp for its documentation and an example launch line.
#pragma once

#include "caustic/engine.hpp"
#include "caustic/mesh_levels.hpp"
#include "caustic/param_store.hpp"
#include "caustic/pool.hpp"

#include <gst/gst.h>

#include <chrono>
#include <functional>
#include <optional>
#include <memory>

namespace caustic::gst {

/// Registers the elements of this project (causticsrc) as a static plugin
/// named "caustic". Safe to call more than once; needs gst_init first.
/// causticd does this; other programs load the same element from the
/// plugin file libgstcaustic.so (plugin.cpp) in GStreamer's plugin folder.
bool register_elements();

/// Adds causticsrc to `plugin`: the one init of the static plugin and of
/// the plugin file.
bool register_element(GstPlugin* plugin);

/// Gives a causticsrc the parameters and the meshes it renders, instead of
/// its `scene` property; each frame draws the level its scene's
/// render.mesh_resolution names. Call before the element leaves the NULL
/// state; the ParamStore stays shared, so patches show in later frames.
/// A scene with water moves `pool` (made from the scene when null); one
/// element at a time may stream a pool.
void set_source(GstElement* causticsrc, std::shared_ptr<ParamStore> params, std::shared_ptr<const MeshLevels> meshes,
                std::shared_ptr<water::Pool> pool = nullptr);

/// When the element's render thread last came round its loop (every few
/// milliseconds, and after each render): a watchdog's proof that rendering
/// is not stuck. None before streaming started or after it stopped.
std::optional<std::chrono::steady_clock::time_point> render_heartbeat(GstElement* causticsrc);

/// Called on the streaming thread for every frame sent while a render has
/// overrun its frame interval (the previous picture goes out instead).
void set_overrun_observer(GstElement* causticsrc, std::function<void()> observer);

/// Called on the render thread after every render (not for re-sent frames).
using FrameObserver = std::function<void(const FrameStats& stats, std::uint64_t version)>;
void set_frame_observer(GstElement* causticsrc, FrameObserver observer);

/// Asks for the picture last rendered and its HDR image: `done` is called
/// on the render thread at its next turn (within a few milliseconds while
/// streaming), with null pointers if the element stops first. A request
/// made while the element does not stream waits for it to start or stop.
/// `colour` is the HDR image in colour for a spectral frame, null for a
/// grey one (`hdr` is then its luminance).
using SnapshotDone = std::function<void(const Rgba8Image* ldr, const HdrImage* hdr, const RgbHdrImage* colour)>;
void request_snapshot(GstElement* causticsrc, SnapshotDone done);

/// Sends the next frame due even if its picture is unchanged (under
/// still-interval-ms): what an encoder that was asked for a key frame, and
/// that keeps the request to itself, needs to make one now. Any thread.
void send_next_frame(GstElement* causticsrc);

/// The water a causticsrc streams: the one set_source() gave, or from when
/// it starts streaming a scene with water the one it made (null for other
/// scenes); drops posted to it fall in the next frame. Any thread.
std::shared_ptr<water::Pool> water_pool(GstElement* causticsrc);

/// The parameters a causticsrc renders (null before a source was set or loaded).
std::shared_ptr<ParamStore> param_store(GstElement* causticsrc);

}  // namespace caustic::gst
