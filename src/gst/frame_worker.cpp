// SPDX-License-Identifier: LGPL-2.1-or-later
#include "frame_worker.hpp"

namespace caustic::gst {

FrameWorker::FrameWorker(FrameSource& source, std::shared_ptr<const ParamStore> params,
                         std::shared_ptr<const MeshLevels> meshes, int width, int height,
                         std::atomic<std::int64_t>* heartbeat, std::function<void()> on_picture,
                         const std::atomic<bool>* flushing)
    : source_(source), params_(std::move(params)), meshes_(std::move(meshes)), width_(width), height_(height),
      heartbeat_(heartbeat), on_picture_(std::move(on_picture)), flushing_(flushing), thread_([this] { run(); }) {}

FrameWorker::~FrameWorker() {
  {
    std::lock_guard lock(lock_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
  if (picture_) gst_buffer_unref(picture_);
}

void FrameWorker::run() {
  std::unique_lock lock(lock_);
  while (!stop_) {
    lock.unlock();
    *heartbeat_ = std::chrono::steady_clock::now().time_since_epoch().count();
    GstBuffer* picture = nullptr;
    std::string error;
    busy_since_ = std::chrono::steady_clock::now().time_since_epoch().count();
    try {
      picture = produce_frame(source_, *params_, *meshes_, width_, height_, true);
    } catch (const std::exception& e) {
      error = e.what();
    }
    busy_since_ = 0;
    answer_snapshots(source_);
    lock.lock();
    // Most turns find nothing new: the same picture comes back.
    if (picture == picture_) {
      if (picture) gst_buffer_unref(picture);
    } else if (picture) {
      if (picture_) gst_buffer_unref(picture_);
      picture_ = picture;
      source_.picture_at = std::chrono::steady_clock::now();
      ready_.notify_all();
      if (on_picture_) on_picture_();
    }
    if (!error.empty()) {
      error_ = error;
      ready_.notify_all();
    }
    if (!error.empty()) break;
    // Parameters have no change signal: look again when the streaming
    // thread asks for a frame, or after a few milliseconds.
    wake_.wait_for(lock, std::chrono::milliseconds(4), [this] { return stop_ || kicked_; });
    kicked_ = false;
  }
  lock.unlock();
  *heartbeat_ = 0;
  release(source_);  // the GL context goes on the thread that made it
}

GstBuffer* FrameWorker::latest(std::chrono::nanoseconds frame_interval) {
  const std::int64_t since = busy_since_.load(), now = std::chrono::steady_clock::now().time_since_epoch().count();
  source_.asked = now;
  if (since != 0 && now - since >
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(frame_interval).count())
    ++overruns_;
  std::unique_lock lock(lock_);
  kicked_ = true;
  wake_.notify_all();
  // The first picture may take a whole render (and the GL context's making):
  // a stop asked meanwhile (unlock()) ends the wait, looked at every 20 ms.
  const auto done = [this] { return picture_ || !error_.empty() || (flushing_ && flushing_->load()); };
  while (!ready_.wait_for(lock, std::chrono::milliseconds(20), done)) {
  }
  // An error comes before the picture: a thread that failed after its
  // first picture has stopped, and sending that picture on would freeze the
  // stream with no word on the bus while changes went unseen.
  if (!error_.empty()) throw std::runtime_error(error_);
  if (picture_) return gst_buffer_ref(picture_);
  return nullptr;
}

}  // namespace caustic::gst
