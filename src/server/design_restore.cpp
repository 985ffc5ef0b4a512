// SPDX-License-Identifier: LGPL-2.1-or-later
// Reading the designs back from their folders when the server starts: each
// folder's meta.json, then what its files say the design had come to.
#include "design_files.hpp"
#include "design_job.hpp"

#include "caustic/json_text.hpp"
#include "log.hpp"

#include <regex>

namespace caustic::server {
namespace fs = std::filesystem;

std::vector<std::shared_ptr<DesignJobs::Job>> DesignJobs::stored() const {
  static const std::regex id_pattern("[0-9a-f]{32}");
  std::vector<std::shared_ptr<Job>> found;
  // One design's broken files skip that design, never the others: each is
  // read in a try of its own, and a link that loops is only a name.
  for (const auto& dir : fs::directory_iterator(settings_.folder)) {
    const std::string id = dir.path().filename().string();
    std::error_code ec;
    if (!std::regex_match(id, id_pattern) || !dir.is_directory(ec)) continue;
    if (fs::exists(dir.path() / kRemovedMark, ec)) {  // deleted while it ran, then stopped
      fs::remove_all(dir.path(), ec);
      continue;
    }
    auto job = std::make_shared<Job>();
    job->id = id;
    job->folder = dir.path();
    try {
      const auto meta = parse_json_text(read_text(dir.path() / "meta.json"));
      if (!meta || !meta->is_object()) throw std::runtime_error("meta.json is not a JSON object");
      job->token = meta->at("token").get<std::string>();
      job->name = meta->at("name").get<std::string>();
      job->extension = meta->at("extension").get<std::string>();
      job->created = meta->at("created").get<std::int64_t>();
      job->colour = meta->value("colour", false);  // absent in designs stored before colour existed
      if (job->extension != ".png" && job->extension != ".jpg") throw std::runtime_error("meta.json: bad extension");
      // An upload's time on this server's clock: far beyond it, the expiry's sum overflowed and removed it.
      if (job->created < 0 || job->created > unix_now() + 24 * 3600)
        throw std::runtime_error("meta.json: \"created\" is not a time this server gave");
      if (!restore(*job)) continue;
    } catch (const std::exception& e) {
      log(Level::warning, "design " + id + " skipped: " + e.what());
      continue;
    }
    found.push_back(job);
  }
  return found;
}

// A stored design's state from what its folder holds; false when it holds
// nothing to go on with. Throws on files that do not read as they should.
bool DesignJobs::restore(Job& job) {
  const fs::path& dir = job.folder;
  std::error_code ec;
  if (fs::exists(dir / "error.txt", ec)) {
    job.state = Job::State::failed;
    // The visitor's words for the failure: short, or the generic ones.
    job.error = read_text(dir / "error.txt", 4096);
    if (job.error.empty()) job.error = "the server could not design this picture";
  } else if (fs::exists(dir / "scene.json", ec) && fs::exists(dir / "report.json", ec)) {
    job.state = Job::State::restoring;
    // What answers need was kept beside the scene: ready at once, and the
    // scene itself is read back only when a session asks for it.
    const auto info = parse_json_text(read_text(dir / "info.json"));
    auto thumbnail = read_text(dir / "thumbnail.png");
    const auto report = parse_json_text(read_text(dir / "report.json"));
    if (info && info->is_object() && report && report->is_object() && !thumbnail.empty()) {
      job.state = Job::State::ready;
      job.info = *info;
      job.thumbnail.assign(thumbnail.begin(), thumbnail.end());
      job.report = public_report(*report);
    }
  } else if (fs::exists(dir / ("picture" + job.extension), ec)) {
    job.state = Job::State::queued;  // interrupted by a stop: design it again
  } else {
    return false;
  }
  return true;
}

}  // namespace caustic::server
