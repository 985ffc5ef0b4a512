// SPDX-License-Identifier: LGPL-2.1-or-later
#include "design_jobs.hpp"

#include "design_files.hpp"
#include "design_job.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/json_text.hpp"
#include "http_util.hpp"
#include "log.hpp"
#include "session.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>

#include <sys/resource.h>
#include <unistd.h>

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

struct Stopping {};
// Thrown by a design's progress when its owner deleted it: the run unwinds
// at once instead of designing for no one while the queue waits.
struct Cancelled {};

}  // namespace

DesignJobs::DesignJobs(DesignSettings settings, DesignBackend backend)
    : settings_(std::move(settings)), backend_(std::move(backend)) {
  fs::create_directories(settings_.folder);
  fs::permissions(settings_.folder, fs::perms::owner_all, fs::perm_options::replace);
  std::vector<std::shared_ptr<Job>> found = stored();
  // Oldest first: restored scenes, then the interrupted uploads in order.
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a->created < b->created; });
  for (const auto& job : found) {
    jobs_[job->id] = job;
    if (job->state == Job::State::restoring) queue_.push_front(job);
    else if (job->state == Job::State::queued) queue_.push_back(job);
  }
  expire_locked(unix_now());
  for (int i = 0; i < std::max(1, settings_.workers); ++i) workers_.emplace_back([this] { work(); });
}

DesignJobs::~DesignJobs() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& worker : workers_) worker.join();
}

void DesignJobs::save_meta(const Job& job) const {
  write_atomic(job.folder / "meta.json", nlohmann::json{{"id", job.id},
                                                        {"token", job.token},
                                                        {"name", job.name},
                                                        {"extension", job.extension},
                                                        {"colour", job.colour},
                                                        {"created", job.created}}
                                             .dump(2));
}

DesignJobs::Ticket DesignJobs::submit(const std::vector<unsigned char>& picture, const std::string& extension,
                                      const std::string& name, bool colour) {
  std::lock_guard lock(mutex_);
  if (pending_locked() >= settings_.queue)
    throw DesignRefusal(503, "the design queue is full (" + std::to_string(settings_.queue) + "); try again later");
  if (static_cast<int>(jobs_.size()) >= settings_.max_stored)
    throw DesignRefusal(503, "the server keeps at most " + std::to_string(settings_.max_stored) +
                                 " designs and holds that many; try again later");
  auto job = std::make_shared<Job>();
  job->id = random_hex();
  job->token = random_hex();
  job->name = name;
  job->colour = colour;
  job->extension = extension;
  job->created = unix_now();
  job->folder = settings_.folder / job->id;
  try {
    std::error_code ec;
    fs::create_directory(job->folder, ec);
    if (!ec) fs::permissions(job->folder, fs::perms::owner_all, fs::perm_options::replace, ec);
    if (ec) throw StorageError(ec.value(), "cannot make the design's folder: " + ec.message());
    write_atomic(job->folder / ("picture" + extension), std::string(picture.begin(), picture.end()));
    save_meta(*job);
  } catch (const StorageError& e) {
    // Nothing of the upload stays: a folder without its picture or its
    // meta.json would be skipped by every start and never expire.
    std::error_code ec;
    fs::remove_all(job->folder, ec);
    refuse_unstored_locked(e);
  }
  if (storage_failing_) log(Level::info, "designs are stored again in " + settings_.folder.string());
  storage_failing_ = false;
  jobs_[job->id] = job;
  queue_.push_back(job);
  wake_.notify_all();
  return {job->id, job->token};
}

void DesignJobs::refuse_unstored_locked(const StorageError& e) {
  // The operator learns where and why, once until a picture is stored
  // again (each refused upload would repeat it); the visitor, that the
  // server has no room, never a path.
  if (!storage_failing_)
    log(Level::error, "picture uploads refused: " + std::string(e.what()) + " in the state directory " +
                          settings_.folder.string());
  storage_failing_ = true;
  if (e.no_room()) throw DesignRefusal(507, "the server has no room to store the picture; try again later");
  throw DesignRefusal(503, "the server cannot store pictures now; try again later");
}

int DesignJobs::pending_locked() const {
  // The designs running are counted by the workers, not by jobs_: one
  // deleted while it runs still holds its worker until it has unwound.
  int n = designing_;
  for (const auto& [id, job] : jobs_) n += job->state == Job::State::queued;
  return n;
}

nlohmann::json DesignJobs::describe(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return nullptr;
  const Job& job = *it->second;
  // A restored design shows as queued until its scene is loaded again.
  const auto state = job.state == Job::State::restoring ? Job::State::queued : job.state;
  nlohmann::json out = {{"id", job.id},
                        {"name", job.name},
                        {"colour", job.colour},
                        {"state", Job::state_name(state)},
                        {"progress", job.state == Job::State::ready ? 1.0 : job.progress},
                        {"created", job.created}};
  if (state == Job::State::queued) {
    int position = 1;
    for (const auto& q : queue_) {
      if (q.get() == &job) break;
      position += q->state == Job::State::queued;
    }
    out["position"] = position;
  }
  if (!job.stage.empty() && state == Job::State::designing) out["stage"] = job.stage;
  if (state == Job::State::failed) out["error"] = job.error;
  if (state == Job::State::ready) {
    out["report"] = job.report;
    out["scene"] = job.id;
  }
  std::error_code ec;
  if (fs::exists(job.folder / "keep", ec)) out["expires"] = nullptr;
  else out["expires"] = expires_at(job);
  return out;
}

DesignJobs::SceneLookup DesignJobs::scene(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second->state != Job::State::ready) return {};
  Job& job = *it->second;
  if (auto entry = job.held.lock()) {
    hold_locked(entry);
    return {entry, false};
  }
  // Out of memory since: read back by a worker, as a restart does.
  if (!job.loading) {
    job.loading = true;
    queue_.push_front(it->second);
    wake_.notify_one();
  }
  return {nullptr, true};
}

std::optional<nlohmann::json> DesignJobs::scene_info(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second->state != Job::State::ready) return std::nullopt;
  return it->second->info;
}

std::vector<unsigned char> DesignJobs::thumbnail(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second->state != Job::State::ready) return {};
  return it->second->thumbnail;
}

void DesignJobs::hold_locked(const std::shared_ptr<const GalleryEntry>& entry) {
  std::erase(recent_, entry);
  recent_.push_front(entry);
  if (recent_.size() > kRecentScenes) recent_.pop_back();
}

bool DesignJobs::remove(const std::string& id, const std::string& token) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || token.empty() || !same_secret(token, it->second->token)) return false;
  // A running job keeps its folder until its next progress report, which
  // unwinds it and throws the folder away; the mark says so to a start that
  // comes first.
  auto job = it->second;
  jobs_.erase(it);
  std::erase(queue_, job);
  std::error_code ec;
  if (job->state != Job::State::designing) fs::remove_all(job->folder, ec);
  else std::ofstream(job->folder / kRemovedMark).put('\n');
  return true;
}

std::int64_t DesignJobs::expires_at(const Job& job) const {
  const std::int64_t kept = settings_.expiry_s;
  return job.created + (job.state == Job::State::failed ? std::min(kept, kFailedKeptS) : kept);
}

void DesignJobs::expire_locked(std::int64_t now) {
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    const Job& job = *it->second;
    std::error_code ec;
    const bool old = expires_at(job) <= now;
    const bool finished =
        job.state == Job::State::ready || job.state == Job::State::failed || job.state == Job::State::restoring;
    if (old && finished && !fs::exists(job.folder / "keep", ec)) {
      log(Level::info, "design " + job.id + " expired");
      // A restoring job a worker holds finds itself gone and cleans up.
      std::erase(queue_, it->second);
      fs::remove_all(job.folder, ec);
      it = jobs_.erase(it);
    } else {
      ++it;
    }
  }
}

void DesignJobs::work() {
  // Designs yield to the streams: a nice value of 10 on this thread alone.
  // Refused (a system call filter without setpriority), designs compete
  // with the streams for the cores: said, since nothing else would show it.
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10) != 0) {
    static std::once_flag said;  // every thread meets the same filter
    std::call_once(said, [error = errno] {
      log(Level::warning, std::string("design threads cannot lower their priority (setpriority: ") +
                              std::strerror(error) + "): designs compete with the streams for the cores");
    });
  }
  std::unique_lock lock(mutex_);
  while (!stop_) {
    if (queue_.empty()) {
      wake_.wait_for(lock, std::chrono::seconds(30));
      expire_locked(unix_now());
      continue;
    }
    auto job = queue_.front();
    queue_.pop_front();
    lock.unlock();
    run_job(job);
    lock.lock();
  }
}

void DesignJobs::run_job(const std::shared_ptr<Job>& job) {
  // Queued: design it. Restoring (a start) or ready but out of memory: read
  // its scene back.
  bool was_ready = false;  // a read-back: its report is already known
  const bool restoring = [&] {
    std::lock_guard lock(mutex_);
    was_ready = job->state == Job::State::ready;
    const bool r = job->state != Job::State::queued;
    if (!r) {
      job->state = Job::State::designing;
      ++designing_;
    }
    return r;
  }();
  // Every way out of a design frees its place in the queue (mutex_ held).
  const auto done_designing = [&] {
    if (!restoring) --designing_;
  };
  const fs::path picture = job->folder / ("picture" + job->extension);
  std::string error;
  std::shared_ptr<const GalleryEntry> entry;
  nlohmann::json report;
  try {
    std::shared_ptr<const Mesh> face;
    if (!restoring) {
      if (!backend_.run) throw DesignFailure("design is not built into this server");
      face = backend_.run(picture, job->folder, settings_.resolution, job->colour,
                          [&](const DesignBackend::Progress& p) {
        std::lock_guard lock(mutex_);
        // A stop unwinds the design: the picture stays, and the next start
        // designs it again.
        if (stop_) throw Stopping();
        const auto it = jobs_.find(job->id);
        if (it == jobs_.end() || it->second != job) throw Cancelled();
        job->progress = p.fraction;
        job->stage = p.stage;
      });
    }
    // Stopped once the design's files are whole: the next start reads it
    // back (a restore), so the stop need not wait for the read-back, seconds
    // of building and drawing at the largest resolution.
    {
      std::lock_guard lock(mutex_);
      if (stop_) throw Stopping();
    }
    if (!was_ready)
      report = public_report(parse_json_text(read_text(job->folder / "report.json")).value_or(nlohmann::json::object()));
    GlContext context(egl_platform_from_environment());
    std::unique_ptr<Engine> engine;
    auto scene = load_entry(job->folder / "scene.json", job->id, [&]() -> Engine& {
      if (!engine) engine = std::make_unique<Engine>();
      return *engine;
    }, 256, std::move(face));
    scene->scene.name = job->name;
    scene->scene.description = "Designed from a visitor's picture.";
    scene->designed = true;
    entry = std::move(scene);
    engine.reset();
    context.release_current();
  } catch (const Stopping&) {
    std::lock_guard lock(mutex_);
    done_designing();
    return;
  } catch (const Cancelled&) {
    std::error_code ec;
    fs::remove_all(job->folder, ec);
    log(Level::info, "design " + job->id + " stopped: deleted by its owner");
    std::lock_guard lock(mutex_);
    done_designing();
    return;
  } catch (const DesignFailure& e) {
    error = e.what();
  } catch (const StorageError& e) {
    // The design was made but cannot be kept: said as such, not blamed on the picture.
    log(Level::error, "design " + job->id + ": " + e.what() + " in the state directory " + settings_.folder.string());
    error = e.no_room() ? "the server had no room to store this design; try again later"
                        : "the server could not store this design";
  } catch (const std::exception& e) {
    log(Level::error, "design " + job->id + ": " + e.what());
    error = "the server could not design this picture";
  }
  std::error_code ec;
  fs::remove(picture, ec);  // the visitor's picture is not kept once designed
  std::lock_guard lock(mutex_);
  done_designing();
  if (!jobs_.count(job->id)) {  // deleted while it ran
    fs::remove_all(job->folder, ec);
    return;
  }
  job->loading = false;
  if (error.empty()) {
    if (job->state != Job::State::ready) {
      log(Level::info, "design " + job->id + (restoring ? " restored" : " ready"));
      try {
        write_atomic(job->folder / "thumbnail.png", std::string(entry->thumbnail_png.begin(), entry->thumbnail_png.end()));
        write_atomic(job->folder / "info.json", caustic::server::describe(*entry).dump());
      } catch (const std::exception& e) {
        log(Level::warning, "design " + job->id + ": " + e.what());  // a later start reads the scene back instead
      }
    }
    job->state = Job::State::ready;
    job->thumbnail = entry->thumbnail_png;
    job->info = caustic::server::describe(*entry);  // the gallery's, not this class's
    job->held = entry;
    hold_locked(entry);
    if (!was_ready) job->report = std::move(report);
    job->progress = 1;
  } else if (restoring) {
    // A design made once and not read back now (no GL for a moment, out of
    // descriptors, a file gone bad): failed for this run only. Its files
    // stay as they were, and the next start tries them again.
    job->state = Job::State::failed;
    job->error = "the server could not read this design back; it tries again when it restarts";
    log(Level::warning, "design " + job->id + " not read back: " + error);
  } else {
    job->state = Job::State::failed;
    job->error = error;
    // What the design wrote before it failed is thrown away, which also
    // makes room for its error; without error.txt the folder would hold
    // nothing a start can go on with, and goes too (the failure is kept
    // in memory until the server stops).
    for (const char* name : {"face.obj", "scene.json", "report.json", "scene.json.part", "report.json.part"})
      fs::remove(job->folder / name, ec);
    try {
      write_atomic(job->folder / "error.txt", error);
    } catch (const StorageError& e) {
      log(Level::error, "design " + job->id + ": " + e.what() + "; its folder is removed");
      fs::remove_all(job->folder, ec);
    }
    log(Level::warning, "design " + job->id + " failed: " + error);
  }
}

}  // namespace caustic::server
