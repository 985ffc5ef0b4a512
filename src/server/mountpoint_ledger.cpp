// SPDX-License-Identifier: LGPL-2.1-or-later
#include "mountpoint_ledger.hpp"

#include "atomic_file.hpp"
#include "caustic/json_text.hpp"
#include "log.hpp"
#include "server_state.hpp"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <optional>
#include <set>
#include <system_error>

namespace caustic::server {
namespace {

// Far above what the most sessions and strays take (about 70 bytes each).
constexpr std::size_t kMaxLedgerBytes = 1 << 20;

bool our_secret(const std::string& s) {
  if (s.size() != kMountpointSecretLength) return false;
  for (const char c : s)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

}  // namespace

std::filesystem::path ledger_file(const std::filesystem::path& folder) { return folder / "mountpoints.json"; }

std::string write_ledger(const std::filesystem::path& file, const MountpointLedger& ledger) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [id, secret] : ledger) list.push_back({{"id", id}, {"secret", secret}});
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) return "cannot create " + file.parent_path().string() + ": " + ec.message();
  // Private: it holds the secrets. Not synced: it is written at every
  // create and destroy on the main loop, and what it guards against is a
  // server killed, not the machine (whose Janus then goes too).
  try {
    write_atomic(file, nlohmann::json{{"mountpoints", list}}.dump() + "\n", 0600, false);
  } catch (const StorageError& e) {
    return e.what();
  }
  return "";
}

MountpointLedger read_ledger(const std::filesystem::path& file, std::size_t limit, std::string* problem) {
  problem->clear();
  const FileText read = read_file_text(file, kMaxLedgerBytes);
  if (read.not_a_file) *problem = "it is not a regular file";
  else if (!read.opened && read.error != ENOENT) *problem = "cannot read it" + why_unread(read);
  else if (read.too_large) *problem = "it is over " + std::to_string(kMaxLedgerBytes) + " bytes";
  else if (read.opened && read.text.empty()) *problem = "it is empty";
  if (!problem->empty() || !read.opened) return {};
  JsonTextError error;
  const std::optional<nlohmann::json> parsed = parse_json_text(read.text, &error);
  if (!parsed) {
    *problem = "it is not JSON: " + error.message;
    return {};
  }
  const nlohmann::json& doc = *parsed;
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
