// SPDX-License-Identifier: LGPL-2.1-or-later
// The render thread behind causticsrc: it owns the GL context and draws
// (produce_frame) whenever the parameters call for it, while the streaming
// thread only picks up the newest finished picture, so a slow render never
// holds up the encoder: the previous picture goes out again, on time.
#pragma once

#include "frame_source.hpp"

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace caustic::gst {

class FrameWorker {
 public:
  /// Starts the thread; `source` must outlive the worker and is used only
  /// by it from now on (its GL context is made and freed on that thread).
  /// `heartbeat` (steady-clock ticks, 0: not running) is set each time the
  /// thread comes round its loop: proof, for a watchdog, that it is not stuck.
  /// `on_picture` (may be empty) is called on the thread each time a new
  /// picture is finished, so that it need not wait for the next frame time.
  /// While `*flushing` (may be null) holds, latest() waits for no picture.
  FrameWorker(FrameSource& source, std::shared_ptr<const ParamStore> params, std::shared_ptr<const MeshLevels> meshes,
              int width, int height, std::atomic<std::int64_t>* heartbeat, std::function<void()> on_picture = {},
              const std::atomic<bool>* flushing = nullptr);
  /// Stops and joins the thread.
  ~FrameWorker();
  FrameWorker(const FrameWorker&) = delete;
  FrameWorker& operator=(const FrameWorker&) = delete;

  /// A new reference to the newest finished picture (waiting only for the
  /// very first, and null when flushing cut that wait short); wakes the
  /// thread to look at the parameters. Counts an
  /// overrun when the thread has been in one render for more than
  /// `frame_interval`. Throws std::runtime_error with the thread's error,
  /// also once a picture was sent: the thread stops at its error.
  GstBuffer* latest(std::chrono::nanoseconds frame_interval);

  int width() const { return width_; }
  int height() const { return height_; }
  std::uint64_t overruns() const { return overruns_.load(); }

 private:
  void run();

  FrameSource& source_;
  std::shared_ptr<const ParamStore> params_;
  std::shared_ptr<const MeshLevels> meshes_;
  int width_, height_;
  std::mutex lock_;
  std::condition_variable wake_, ready_;
  bool stop_ = false, kicked_ = false;
  GstBuffer* picture_ = nullptr;  // newest finished, guarded by lock_
  std::string error_;
  std::atomic<std::int64_t> busy_since_{0};  // steady-clock ticks when the current render began; 0: idle
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<std::int64_t>* heartbeat_;
  std::function<void()> on_picture_;
  const std::atomic<bool>* flushing_;
  std::thread thread_;
};

}  // namespace caustic::gst
