// SPDX-License-Identifier: LGPL-2.1-or-later
// Visitors' pictures turned into glass: uploads wait in a bounded queue, a
// worker thread of low priority designs them one at a time (so that the
// streams keep their cores), and each finished design becomes a scene that
// only those who hold its id can open. Every design lives in a folder of its
// own under the state directory, survives a restart and expires unless the
// operator keeps it (a file named `keep` in its folder).
#pragma once

#include "gallery.hpp"

#include <nlohmann/json.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace caustic::server {

/// Why a picture cannot be designed, in words for the visitor who sent it
/// (no file names, no library messages). Anything else a job throws is the
/// server's problem: logged, and reported to the visitor in general terms.
struct DesignFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a design job does between "picture on disk" and "scene on disk";
/// design_backend.cpp when the designer is built in, a refusal otherwise.
struct DesignBackend {
  struct Progress {
    double fraction = 0;  ///< 0..1 of the whole job
    std::string stage;    ///< "designing", "checking"
  };
  /// Writes face.obj, scene.json and report.json into `folder` from
  /// `target` (in colour: a tinted face, docs/design.md "Colour") and
  /// returns the face (so that it need not be read back);
  /// throws DesignFailure for a picture that cannot be designed. `progress`
  /// may throw (the server is stopping): the run then unwinds.
  std::function<std::shared_ptr<const Mesh>(const std::filesystem::path& target, const std::filesystem::path& folder,
                                            int resolution, bool colour,
                                            const std::function<void(const Progress&)>& progress)>
      run;
  bool built_in = false;
  /// The most pixels a side the designer takes (its own limit), checked at
  /// upload so that a picture it would refuse takes no place in the queue.
  std::uint32_t max_side = 0;
};
DesignBackend design_backend();

struct DesignSettings {
  std::filesystem::path folder;  ///< <state>/designs
  int queue = 4;                 ///< designs waiting or running at once; 503 beyond
  int workers = 1;               ///< designs running at once
  int resolution = 512;
  long long expiry_s = 7 * 24 * 3600;
  int max_stored = 100;          ///< designs kept (any state); 503 beyond
};

struct StorageError;  // design_files.hpp

/// A refused upload: HTTP status and a detail for problem+json.
struct DesignRefusal : std::runtime_error {
  DesignRefusal(unsigned status, const std::string& detail) : std::runtime_error(detail), status(status) {}
  unsigned status;
};

class DesignJobs {
 public:
  /// Reads the designs already in `settings.folder` (finished ones are
  /// loaded, unfinished ones queued again) and starts the worker.
  DesignJobs(DesignSettings settings, DesignBackend backend);
  ~DesignJobs();
  DesignJobs(const DesignJobs&) = delete;
  DesignJobs& operator=(const DesignJobs&) = delete;

  struct Ticket {
    std::string id, token;
  };
  /// Queues a checked picture (its bytes and the file extension that names
  /// its format). Throws DesignRefusal: 503 when the queue is full or the
  /// state directory fails, 507 when it has no room for the picture.
  Ticket submit(const std::vector<unsigned char>& picture, const std::string& extension, const std::string& name,
                bool colour = false);

  /// Public state of a design: id, name, state, progress, position in the
  /// queue, error, the picture figures of its report, its scene id. Null
  /// when there is no such design.
  nlohmann::json describe(const std::string& id) const;
  /// The scene of a finished design. Only a few stay in memory (each is
  /// tens of MB): one that is not is queued to be read back, and `loading`
  /// says so (ask again in a moment). Both empty: no such finished design.
  struct SceneLookup {
    std::shared_ptr<const GalleryEntry> entry;
    bool loading = false;
  };
  SceneLookup scene(const std::string& id);
  /// What GET /api/v1/scenes/{id} answers, and the thumbnail, for a finished
  /// design, without reading its scene back; empty when there is none.
  std::optional<nlohmann::json> scene_info(const std::string& id) const;
  std::vector<unsigned char> thumbnail(const std::string& id) const;
  /// Removes a design when `token` is its owner's; false otherwise.
  bool remove(const std::string& id, const std::string& token);
  bool built_in() const { return backend_.built_in; }
  std::uint32_t max_side() const { return backend_.max_side; }

 private:
  struct Job;
  // A stored design's state from what its folder holds; false when it holds
  // nothing to go on with. Throws on files that do not read as they should.
  static bool restore(Job& job);
  // Every design its folder holds (design_restore.cpp), read at the start.
  std::vector<std::shared_ptr<Job>> stored() const;
  // When `job` is thrown away (a failed one sooner), unless it is kept.
  std::int64_t expires_at(const Job& job) const;
  void work();
  void run_job(const std::shared_ptr<Job>& job);
  void expire_locked(std::int64_t now);
  int pending_locked() const;
  void hold_locked(const std::shared_ptr<const GalleryEntry>& entry);
  void save_meta(const Job& job) const;
  // Logs and throws the DesignRefusal for an upload that could not be stored.
  [[noreturn]] void refuse_unstored_locked(const StorageError& e);

  DesignSettings settings_;
  DesignBackend backend_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::deque<std::shared_ptr<Job>> queue_;
  /// The scenes last used, newest first: kept in memory for the next session.
  static constexpr std::size_t kRecentScenes = 4;
  std::deque<std::shared_ptr<const GalleryEntry>> recent_;
  bool stop_ = false;
  bool storage_failing_ = false;  ///< the last upload could not be stored (logged once)
  int designing_ = 0;  ///< designs the workers run now, deleted ones included
  std::vector<std::thread> workers_;
};

}  // namespace caustic::server
