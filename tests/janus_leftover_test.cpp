// SPDX-License-Identifier: LGPL-2.1-or-later
// The ledger of mountpoints in the state folder: a causticd killed with
// SIGKILL leaves its mountpoints in a Janus that keeps running, and the next
// start on the same state folder destroys them; a damaged ledger is said
// and ignored; a clean stop leaves it empty. Its file read and written
// alone first (MountpointLedger), then against a real Janus (Broadcast).
#include "janus_fixture.hpp"

#include "../src/server/mountpoint_ledger.hpp"

#include <sys/stat.h>

#include <csignal>
#include <set>

using namespace caustic::testing::janus_fixture;
using caustic::server::MountpointLedger;
using caustic::server::read_ledger;
using caustic::server::write_ledger;

namespace {

const std::string kSecret(32, 'a');

// A folder of the test's own, removed with it.
struct TempFolder {
  fs::path path = fs::temp_directory_path() / ("causticd_ledger_" + std::to_string(::getpid()));
  TempFolder() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempFolder() { fs::remove_all(path); }
};

// What read_ledger makes of `text`: the mountpoints, and the problem.
std::pair<MountpointLedger, std::string> read_text(const std::string& text, std::size_t limit = 10) {
  TempFolder folder;
  const fs::path file = folder.path / "mountpoints.json";
  std::ofstream(file, std::ios::binary) << text;
  std::string problem;
  MountpointLedger ledger = read_ledger(file, limit, &problem);
  return {ledger, problem};
}

}  // namespace

TEST(MountpointLedger, WrittenWholeAndPrivateAndReadBack) {
  TempFolder folder;
  const fs::path file = caustic::server::ledger_file(folder.path / "state");
  const MountpointLedger ledger{{1, kSecret}, {281474976710655u, std::string(16, '0') + std::string(16, 'f')}};
  ASSERT_EQ(write_ledger(file, ledger), "");
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u) << "it holds the secrets";
  EXPECT_FALSE(fs::exists(file.string() + ".part")) << "the temporary file stayed";
  std::string problem;
  EXPECT_EQ(read_ledger(file, 10, &problem), ledger);
  EXPECT_EQ(problem, "");
  // Rewritten empty; a missing ledger lists nothing and is no problem.
  ASSERT_EQ(write_ledger(file, {}), "");
  EXPECT_TRUE(read_ledger(file, 10, &problem).empty());
  EXPECT_EQ(problem, "");
  fs::remove(file);
  EXPECT_TRUE(read_ledger(file, 10, &problem).empty());
  EXPECT_EQ(problem, "");
  // A folder in the ledger's place: the write fails and says why.
  fs::create_directories(file);
  EXPECT_NE(write_ledger(file, ledger), "");
}

TEST(MountpointLedger, ADamagedLedgerListsNothingAndSaysWhy) {
  const std::string ok = R"({"id": 7, "secret": ")" + kSecret + R"("})";
  for (const std::string& text : {std::string("\x89PNG\r\n\x1a\n\0\xff", 10), std::string(""), std::string("[]"),
                                  std::string(R"({"mountpoints": {}})"), std::string(R"({"mountpoints": [3]})"),
                                  R"({"mountpoints": [)" + ok + R"(, {"id": 0, "secret": ")" + kSecret + R"("}]})",
                                  R"({"mountpoints": [{"id": "7", "secret": ")" + kSecret + R"("}]})",
                                  R"({"mountpoints": [{"id": -7, "secret": ")" + kSecret + R"("}]})",
                                  R"({"mountpoints": [{"id": 7.5, "secret": ")" + kSecret + R"("}]})",
                                  std::string(R"({"mountpoints": [{"id": 7, "secret": 12}]})"),
                                  R"({"mountpoints": [{"id": 7, "secret": ")" + std::string(31, 'a') + R"("}]})",
                                  R"({"mountpoints": [{"id": 7, "secret": ")" + std::string(32, 'A') + R"("}]})",
                                  R"({"mountpoints": [{"id": 7, "secret": ")" + std::string(31, 'a') + R"(g"}]})",
                                  std::string(2 << 20, ' ') + R"({"mountpoints": []})", std::string(100000, '[')}) {
    const auto [ledger, problem] = read_text(text);
    EXPECT_TRUE(ledger.empty()) << text.substr(0, 200);
    EXPECT_NE(problem, "") << text.substr(0, 200);
  }
  const auto [ledger, problem] = read_text(R"({"mountpoints": [)" + ok + "]}");
  EXPECT_EQ(ledger, (MountpointLedger{{7, kSecret}}));
  EXPECT_EQ(problem, "");
}

TEST(MountpointLedger, NoMoreThanTheServerHoldsIsRead) {
  std::string text = R"({"mountpoints": [)";
  for (int id = 1; id <= 5; ++id) text += (id > 1 ? "," : "") + (R"({"id": )" + std::to_string(id)) + R"(, "secret": ")" + kSecret + "\"}";
  const auto [ledger, problem] = read_text(text + "]}", 3);
  EXPECT_EQ(ledger.size(), 3u);
  EXPECT_NE(problem.find("5 mountpoints"), std::string::npos) << problem;
}

TEST(MountpointLedger, AFifoInItsPlaceHoldsNothing) {
  TempFolder folder;
  const fs::path file = folder.path / "mountpoints.json";
  ASSERT_EQ(::mkfifo(file.c_str(), 0600), 0);
  std::string problem;
  EXPECT_TRUE(read_ledger(file, 10, &problem).empty());
  EXPECT_NE(problem, "");
}

namespace {

// The mountpoint of broadcast `s`, as its viewer link names it (0 if none).
std::uint64_t mountpoint_of(const std::string& url, const json& s) {
  const auto r = http("POST", url + s.value("viewers_url", ""), "", "", bearer_token(s.value("token", "")));
  return r.status == 201 ? r.json().value("mountpoint", std::uint64_t{0}) : 0;
}

std::set<std::uint64_t> ids_of(const json& list) {
  std::set<std::uint64_t> ids;
  for (const auto& m : list.value("list", json::array())) ids.insert(m.value("id", std::uint64_t{0}));
  return ids;
}

MountpointLedger ledger_in(const fs::path& state) {
  std::string problem;
  MountpointLedger ledger = read_ledger(caustic::server::ledger_file(state), 1000, &problem);
  EXPECT_EQ(problem, "");
  return ledger;
}

}  // namespace

TEST_F(Broadcast, MountpointsOfAKilledServerGoAtTheNextStart) {
  server_.reset();
  const fs::path state = dir_ / "state", log = dir_ / "causticd.log";
  const std::vector<std::string> args{"--set", "state_dir=" + state.string()};
  server_ = start_server(args, log);
  ASSERT_FALSE(server_->url().empty());
  const std::uint64_t id = mountpoint_of(server_->url(), create_broadcast());
  ASSERT_NE(id, 0u);
  EXPECT_EQ(ledger_in(state).count(id), 1u) << "the ledger does not list the running mountpoint";
  server_->signal(SIGKILL);
  server_->wait_exit(10000);
  ASSERT_EQ(server_->pid(), "") << "SIGKILL did not end the server";
  ASSERT_EQ(ids_of(admin({{"request", "list"}})).count(id), 1u) << "the killed server's mountpoint is not in Janus";
  // One Janus never made (a create sent as the server died): Janus twice
  // says it has none, and it leaves the ledger too.
  MountpointLedger listed = ledger_in(state);
  listed[5] = std::string(32, 'c');
  ASSERT_EQ(write_ledger(caustic::server::ledger_file(state), listed), "");

  server_ = start_server(args, log);
  ASSERT_FALSE(server_->url().empty());
  bool gone = false;
  for (int i = 0; i < 200 && !gone; ++i, g_usleep(100000)) {
    const json list = admin({{"request", "list"}});
    gone = list.contains("list") && ids_of(list).count(id) == 0 && ledger_in(state).empty();
  }
  EXPECT_TRUE(gone) << "the mountpoint outlived the server that made it: " << admin({{"request", "list"}}).dump();
  EXPECT_NE(ct::read_file(log).find("mountpoint " + std::to_string(id) + ", left in Janus by an earlier run"),
            std::string::npos)
      << ct::read_file(log);
  // And the new server broadcasts.
  EXPECT_NE(mountpoint_of(server_->url(), create_broadcast()), 0u);
}

TEST_F(Broadcast, ADamagedLedgerIsSaidAndBroadcastsGoOn) {
  server_.reset();
  const fs::path state = dir_ / "state", log = dir_ / "causticd.log";
  const fs::path file = caustic::server::ledger_file(state);
  const std::string secret(32, 'b');
  for (const std::string& text : {std::string("\x89PNG\r\n\x1a\n\0\xff", 10), std::string(R"({"mountpoints": 7})"),
                                  R"({"mountpoints": [{"id": 0, "secret": ")" + secret + R"("}]})",
                                  R"({"mountpoints": [{"id": "12", "secret": ")" + secret + R"("}]})"}) {
    SCOPED_TRACE(text);
    fs::create_directories(state);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    fs::remove(log);
    server_ = start_server({"--set", "state_dir=" + state.string()}, log);
    ASSERT_FALSE(server_->url().empty());
    const std::uint64_t id = mountpoint_of(server_->url(), create_broadcast());
    EXPECT_NE(id, 0u);
    // A warning (priority 4) naming the file.
    const std::string said = ct::read_file(log);
    const auto at = said.find(file.string());
    ASSERT_NE(at, std::string::npos) << said;
    const auto line = said.rfind('\n', at);
    EXPECT_EQ(said.substr(line == std::string::npos ? 0 : line + 1, 3), "<4>") << said;
    const MountpointLedger now = ledger_in(state);
    EXPECT_EQ(now.size(), 1u) << "the damaged ledger was not replaced";
    EXPECT_EQ(now.count(id), 1u);
    server_.reset();
  }
}

TEST_F(Broadcast, ACleanStopLeavesAnEmptyLedger) {
  server_.reset();
  const fs::path state = dir_ / "state";
  server_ = start_server({"--set", "state_dir=" + state.string()});
  ASSERT_FALSE(server_->url().empty());
  create_broadcast();
  create_broadcast();
  EXPECT_EQ(ledger_in(state).size(), 2u);
  server_->signal(SIGTERM);
  EXPECT_EQ(server_->wait_exit(10000), 0);
  EXPECT_TRUE(fs::exists(caustic::server::ledger_file(state)));
  EXPECT_TRUE(ledger_in(state).empty());
}

TEST_F(Broadcast, AStateFolderThatCannotBeWrittenIsSaidOnceAndBroadcastsGoOn) {
  server_.reset();
  const fs::path state = dir_ / "state", log = dir_ / "causticd.log";
  fs::create_directories(caustic::server::ledger_file(state) / "in-the-way");  // a folder where the file goes
  server_ = start_server({"--set", "state_dir=" + state.string()}, log);
  ASSERT_FALSE(server_->url().empty());
  const json first = create_broadcast(), second = create_broadcast();
  EXPECT_NE(mountpoint_of(server_->url(), first), 0u);
  EXPECT_NE(mountpoint_of(server_->url(), second), 0u);
  const std::string said = ct::read_file(log);
  const std::string warning = "mountpoints cannot be listed";
  const auto at = said.find(warning);
  EXPECT_NE(at, std::string::npos) << said;
  EXPECT_EQ(said.find(warning, at + 1), std::string::npos) << "said more than once: " << said;
}
