// SPDX-License-Identifier: LGPL-2.1-or-later
#include "mountpoint_ledger.hpp"

#include "log.hpp"
#include "server_state.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <set>
#include <system_error>

namespace caustic::server {
namespace {

// Far above what the most sessions and strays take (about 70 bytes each).
constexpr off_t kMaxLedgerBytes = 1 << 20;

std::string errno_text() { return std::strerror(errno); }

bool our_secret(const std::string& s) {
  if (s.size() != kMountpointSecretLength) return false;
  for (const char c : s)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

// The file's text, "" with `*problem` set when it cannot be read. Opened
// without blocking and checked as opened: a FIFO or a device put in its
// place neither holds the start nor is read endlessly.
std::string read_text(const std::filesystem::path& file, std::string* problem) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) *problem = "cannot open it: " + errno_text();
    return "";
  }
  std::string text;
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    *problem = "cannot read it: " + errno_text();
  } else if (!S_ISREG(st.st_mode)) {
    *problem = "it is not a regular file";
  } else if (st.st_size > kMaxLedgerBytes) {
    *problem = "it is over " + std::to_string(kMaxLedgerBytes) + " bytes";
  } else {
    // Read to one byte past the limit: a file that grows meanwhile is caught too.
    char buffer[65536];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) != 0;) {
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        *problem = "cannot read it: " + errno_text();
        break;
      }
      text.append(buffer, static_cast<std::size_t>(n));
      if (text.size() > static_cast<std::size_t>(kMaxLedgerBytes)) {
        *problem = "it is over " + std::to_string(kMaxLedgerBytes) + " bytes";
        break;
      }
    }
  }
  ::close(fd);
  return problem->empty() ? text : "";
}

}  // namespace

std::filesystem::path ledger_file(const std::filesystem::path& folder) { return folder / "mountpoints.json"; }

std::string write_ledger(const std::filesystem::path& file, const MountpointLedger& ledger) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [id, secret] : ledger) list.push_back({{"id", id}, {"secret", secret}});
  const std::string text = nlohmann::json{{"mountpoints", list}}.dump() + "\n";
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) return "cannot create " + file.parent_path().string() + ": " + ec.message();
  // A temporary file renamed over the ledger: a server killed while writing
  // leaves the old ledger whole, never half of a new one.
  const std::filesystem::path temporary = file.string() + ".new";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) return "cannot write " + temporary.string() + ": " + errno_text();
  std::string problem;
  // One left by an earlier run may have another mode.
  if (::fchmod(fd, 0600) != 0) problem = "cannot make " + temporary.string() + " private: " + errno_text();
  for (std::size_t done = 0; problem.empty() && done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) problem = "cannot write " + temporary.string() + ": " + errno_text();
    else done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0 && problem.empty()) problem = "cannot write " + temporary.string() + ": " + errno_text();
  if (problem.empty() && ::rename(temporary.c_str(), file.c_str()) != 0)
    problem = "cannot rename " + temporary.string() + " to " + file.string() + ": " + errno_text();
  if (!problem.empty()) ::unlink(temporary.c_str());
  return problem;
}

MountpointLedger read_ledger(const std::filesystem::path& file, std::size_t limit, std::string* problem) {
  problem->clear();
  const std::string text = read_text(file, problem);
  if (!problem->empty() || text.empty()) {
    std::error_code ec;
    if (problem->empty() && std::filesystem::exists(file, ec)) *problem = "it is empty";
    return {};
  }
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded()) {
    *problem = "it is not JSON";
    return {};
  }
  const auto list = doc.is_object() ? doc.find("mountpoints") : doc.end();
  if (!doc.is_object() || list == doc.end() || !list->is_array()) {
    *problem = "it is not an object with a \"mountpoints\" array";
    return {};
  }
  MountpointLedger ledger;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const nlohmann::json& entry = (*list)[i];
    const auto id = entry.is_object() ? entry.find("id") : entry.end();
    const auto secret = entry.is_object() ? entry.find("secret") : entry.end();
    if (!entry.is_object() || id == entry.end() || !id->is_number_unsigned() || id->get<std::uint64_t>() == 0) {
      *problem = "mountpoint " + std::to_string(i) + " has no positive integer \"id\"";
      return {};
    }
    if (secret == entry.end() || !secret->is_string() || !our_secret(secret->get<std::string>())) {
      *problem = "mountpoint " + std::to_string(i) + " has no \"secret\" of " +
                 std::to_string(kMountpointSecretLength) + " lowercase hex digits";
      return {};
    }
    ledger[id->get<std::uint64_t>()] = secret->get<std::string>();
  }
  if (ledger.size() > limit) {
    *problem = "it lists " + std::to_string(ledger.size()) + " mountpoints, more than the server holds; only the first " +
               std::to_string(limit) + " are destroyed";
    ledger.erase(std::next(ledger.begin(), static_cast<std::ptrdiff_t>(limit)), ledger.end());
  }
  return ledger;
}

void record_mountpoints(const ServerState& s) {
  if (!s.janus) return;
  MountpointLedger ledger;
  for (const auto& [sid, m] : s.mountpoints) ledger[m.id] = m.secret;
  for (const auto& [mid, m] : s.creating) ledger[mid] = m.secret;
  for (const auto& [mid, stray] : s.strays) ledger[mid] = stray.m.secret;
  // Said once per spell: broadcasts go on, only a kill would leave their
  // mountpoints behind.
  static std::set<std::filesystem::path> failing;
  const auto file = ledger_file(state_folder(s.config));
  if (const std::string problem = write_ledger(file, ledger); problem.empty())
    failing.erase(file);
  else if (failing.insert(file).second)
    log(Level::warning, "broadcasts: mountpoints cannot be listed, so a server killed would leave them in Janus: " + problem);
}

}  // namespace caustic::server
