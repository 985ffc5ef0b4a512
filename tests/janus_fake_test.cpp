// SPDX-License-Identifier: LGPL-2.1-or-later
// Broadcasts against a stand-in for Janus's admin API (janus_fake.hpp), for
// orders of answers that a real Janus gives only by chance: a session that
// ends while Janus is creating its mountpoint again (after a Janus restart).
// Whatever Janus makes then is destroyed, and it stays in the state folder's
// list of mountpoints until Janus has said it is gone.
#include "helper_processes.hpp"
#include "janus_fake.hpp"
#include "raw_http.hpp"
#include "server_process.hpp"

#include "../src/server/mountpoint_ledger.hpp"

#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <set>

using caustic::testing::bearer_token;
using caustic::testing::FakeJanus;
using caustic::testing::http;
using caustic::testing::port_of;
using caustic::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A UDP socket on 127.0.0.1 (port 0: any); -1 if the port is taken.
int udp_socket(int port) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), size) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size) != 0) {
    if (fd >= 0) ::close(fd);
    return -1;
  }
  return fd;
}

// The ports a mountpoint would have, held by the test so that the stream
// sent there reaches a socket: video, its RTCP on the next, and data.
struct MountpointPorts {
  std::vector<int> fds;
  int video = 0, data = 0;
  MountpointPorts() {
    for (int attempt = 0; attempt < 20 && fds.empty(); ++attempt) {
      const int v = udp_socket(0);
      const int rtcp = v >= 0 && port_of(v) < 65535 ? udp_socket(port_of(v) + 1) : -1;
      if (rtcp < 0) {
        if (v >= 0) ::close(v);
        continue;
      }
      fds = {v, rtcp, udp_socket(0)};
      video = port_of(v);
      data = fds[2] >= 0 ? port_of(fds[2]) : 0;
    }
  }
  ~MountpointPorts() {
    for (const int fd : fds)
      if (fd >= 0) ::close(fd);
  }
};

// Whether a create names its video port: a mountpoint made again on the
// ports it had (after a Janus restart), not a session's first.
bool names_its_ports(const json& create) {
  const json media = create.value("media", json::array());
  return media.is_array() && !media.empty() && media[0].is_object() && media[0].value("port", 0) != 0;
}

// The streaming plugin's answers, as Janus gives them; `rtcp` ports after
// the video's, its RTCP (1 unless Janus found the next port taken).
json created(std::uint64_t id, const MountpointPorts& p, int rtcp = 1) {
  return {{"streaming", "created"},
          {"create", "causticd"},
          {"permanent", false},
          {"stream",
           {{"id", id}, {"type", "live"}, {"is_private", true},
            {"ports", {{{"type", "video"}, {"mid", "v"}, {"port", p.video}, {"rtcp_port", p.video + rtcp}},
                       {{"type", "data"}, {"mid", "d"}, {"port", p.data}}}}}}};
}
json none(std::uint64_t id) {
  return {{"streaming", "event"}, {"error_code", 455}, {"error", "No such mountpoint/stream " + std::to_string(id)}};
}
json destroyed(std::uint64_t id) { return {{"streaming", "destroyed"}, {"id", id}}; }
json refused() { return {{"streaming", "event"}, {"error_code", 450}, {"error", "Unauthorized (wrong secret)"}}; }

// Janus restarted while a broadcast runs: it has lost the mountpoint
// ("info" answers 455), so causticd creates it again; that create is held
// until the test answers it. Destroys are held too while `holding`.
class FakeBroadcast : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(ports_.fds.empty()) << "no free UDP ports for the mountpoint";
    ASSERT_FALSE(fake_.url().empty()) << "the fake Janus could not listen";
    fs::remove_all(state_);
    const std::string secret(32, 's');
    server_ = std::make_unique<ServerProcess>(std::vector<std::string>{
        "--width", "320", "--height", "240", "--set", "janus_admin_url=" + fake_.url(), "--set",
        "janus_admin_secret=" + secret, "--set", "janus_streaming_key=" + secret, "--set", "janus_token_secret=" + secret,
        "--set", "janus_ws_url=ws://127.0.0.1:8188/", "--set", "drain_timeout_s=0", "--set", "state_dir=" + state_.string()});
    ASSERT_FALSE(server_->url().empty());
  }
  void TearDown() override {
    holding_ = false;
    server_.reset();
    fs::remove_all(state_);
  }

  std::optional<json> script(const json& r) {
    const std::string what = r.value("request", "");
    const auto id = r.value("id", std::uint64_t{0});
    if (what == "create") {
      const bool again = names_its_ports(r);
      if (again ? ++recreates_ == 1 : hold_first_create_.load()) return std::nullopt;
      if (!again && split_creates_ > 0) return --split_creates_, created(id, ports_, 3);
      return created(id, ports_);
    }
    if (what == "info") return lost_ ? none(id) : json{{"streaming", "info"}, {"info", {{"id", id}}}};
    if (what == "destroy" && holding_) return std::nullopt;
    if (what == "destroy" && refuse_destroys_) return refused();
    return what == "destroy" ? none(id) : json::object();
  }

  // A broadcast running, and the re-create of its mountpoint held: the
  // session's id and token, and the mountpoint's id.
  std::tuple<std::string, std::string, std::uint64_t> broadcast_being_recreated() {
    const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
    EXPECT_EQ(r.status, 201u) << r.body;
    const int create = fake_.wait_for(0, [](const json& q) { return q.value("request", "") == "create"; });
    EXPECT_GE(create, 0);
    const std::uint64_t id = create >= 0 ? fake_.request(create).value("id", std::uint64_t{0}) : 0;
    recreate_ = fake_.wait_for(create + 1, [&](const json& q) { return q.value("request", "") == "create"; });
    return {r.json().value("id", ""), r.json().value("token", ""), id};
  }
  // The same broadcast's session ended and its destroy seen: the
  // mountpoint's id and that destroy's request (-1: not seen).
  std::pair<std::uint64_t, int> ended_while_made_again() {
    const auto [session, token, id] = broadcast_being_recreated();
    EXPECT_GE(recreate_, 0) << "causticd did not create the lost mountpoint again";
    if (recreate_ < 0) return {id, -1};
    end_session(session, token);
    const int first = destroy_of(id, recreate_ + 1);
    EXPECT_GE(first, 0) << "the session's end did not destroy its mountpoint";
    return {id, first};
  }
  // A session's first creates seen so far (a re-create names its ports).
  std::vector<std::uint64_t> first_creates() {
    std::vector<std::uint64_t> ids;
    const auto first = [](const json& q) { return q.value("request", "") == "create" && !names_its_ports(q); };
    for (int i = fake_.wait_for(0, first, 0); i >= 0; i = fake_.wait_for(i + 1, first, 0))
      ids.push_back(fake_.request(i).value("id", std::uint64_t{0}));
    return ids;
  }
  int destroy_of(std::uint64_t id, std::size_t from, int seconds = 20) {
    return fake_.wait_for(
        from, [&](const json& q) { return q.value("request", "") == "destroy" && q.value("id", std::uint64_t{0}) == id; },
        seconds);
  }
  void end_session(const std::string& session, const std::string& token) {
    const auto r = http("DELETE", server_->url() + "/api/v1/sessions/" + session, "", "", bearer_token(token));
    EXPECT_LT(r.status, 300u) << r.body;
  }

  // The state folder's list: its ids, and its file's inode (each write
  // renames a new file over it).
  std::set<std::uint64_t> listed() const {
    std::string problem;
    std::set<std::uint64_t> ids;
    for (const auto& [id, secret] : caustic::server::read_ledger(ledger_, 100, &problem)) ids.insert(id);
    EXPECT_EQ(problem, "");
    return ids;
  }
  ino_t ledger_inode() const {
    struct stat st {};
    return ::stat(ledger_.c_str(), &st) == 0 ? st.st_ino : 0;
  }
  // Waits (up to 20 s) for the list to be written again after `before`.
  bool rewritten(ino_t before) const {
    for (int i = 0; i < 200; ++i, g_usleep(100000))
      if (const ino_t now = ledger_inode(); now != 0 && now != before) return true;
    return false;
  }
  bool unlisted(std::uint64_t id) const {
    for (int i = 0; i < 200; ++i, g_usleep(100000))
      if (!listed().count(id)) return true;
    return false;
  }

  MountpointPorts ports_;
  std::atomic<bool> holding_{true};
  std::atomic<bool> hold_first_create_{false};  // a session's first create, held too
  std::atomic<int> split_creates_{0};  // first creates answered with RTCP apart from RTP
  std::atomic<bool> lost_{true};  // "info" says Janus has no such mountpoint
  std::atomic<bool> refuse_destroys_{false};  // destroys answered with a refusal
  int recreates_ = 0;  // on the fake's thread alone
  int recreate_ = -1;  // the held re-create's request
  FakeJanus fake_{[this](const json& r) { return script(r); }};
  fs::path state_ = fs::temp_directory_path() / ("causticd_fake_janus_" + std::to_string(::getpid()));
  fs::path ledger_ = caustic::server::ledger_file(state_);
  std::unique_ptr<ServerProcess> server_;
};

}  // namespace

// The session's destroy reaches Janus before the create it answers "none";
// Janus then makes the mountpoint. It is destroyed again, and listed until
// Janus says it is gone: a server killed meanwhile would destroy it at its
// next start.
TEST_F(FakeBroadcast, AMountpointMadeAgainAfterItsSessionEndedIsDestroyed) {
  const auto [id, first] = ended_while_made_again();
  ASSERT_GE(first, 0);
  const ino_t before = ledger_inode();
  fake_.answer(first, none(id));
  ASSERT_TRUE(rewritten(before)) << "the destroy's answer was not taken";
  EXPECT_TRUE(listed().count(id)) << "unlisted while Janus may still make it";
  fake_.answer(recreate_, created(id, ports_));
  const int again = destroy_of(id, first + 1);
  ASSERT_GE(again, 0) << "the mountpoint Janus made after the session ended stays in Janus";
  EXPECT_TRUE(listed().count(id));
  fake_.answer(again, destroyed(id));
  EXPECT_TRUE(unlisted(id));
  EXPECT_FALSE(fake_.abandoned(recreate_)) << "answered too late: causticd gave up on the create";
}

// The same, with the answers to the create and to the session's destroy
// crossing: the destroy's "none", taken after the create's answer, says
// nothing of the mountpoint made since, whose own destroy is asked again
// until Janus answers it.
TEST_F(FakeBroadcast, ADestroysAnswerThatCrossesTheCreateIsNotTheLastWord) {
  const auto [id, first] = ended_while_made_again();
  ASSERT_GE(first, 0);
  fake_.answer(recreate_, created(id, ports_));
  const int second = destroy_of(id, first + 1);
  ASSERT_GE(second, 0) << "the mountpoint Janus made after the session ended stays in Janus";
  // Not the first asked again once causticd gave up on it: the answer to
  // the create is what sent it.
  ASSERT_FALSE(fake_.abandoned(first)) << "the create's answer did not destroy the mountpoint";
  // In either order: the first "none", then a refusal of the second.
  fake_.answer(first, none(id));
  fake_.answer(second, refused());
  const int third = destroy_of(id, second + 1);
  ASSERT_GE(third, 0) << "a destroy refused was not asked again";
  EXPECT_TRUE(listed().count(id));
  fake_.answer(third, destroyed(id));
  EXPECT_TRUE(unlisted(id));
}

// Janus takes the create but never answers it (frozen past causticd's
// timeout) while the session ends: it may make it still, so it is asked
// to destroy it once causticd gives up.
TEST_F(FakeBroadcast, AnUnansweredCreateAfterItsSessionEndedIsDestroyed) {
  const auto [id, first] = ended_while_made_again();
  ASSERT_GE(first, 0);
  fake_.answer(first, none(id));
  // Asked once causticd gives up on the create (its timeout: 5 s).
  const int again = destroy_of(id, first + 1, 60);
  ASSERT_GE(again, 0) << "a create that may yet be carried out was forgotten";
  fake_.answer(again, destroyed(id));
  EXPECT_TRUE(unlisted(id));
}

// A server stopped while the create is on its way destroys the mountpoint
// once (it is its session's and a create's): each request costs the stop
// a wait on Janus.
TEST_F(FakeBroadcast, AServerStoppedWhileItsMountpointIsMadeAgainAsksOnceForItsDestroy) {
  const auto [session, token, id] = broadcast_being_recreated();
  ASSERT_GE(recreate_, 0) << "causticd did not create the lost mountpoint again";
  holding_ = false;
  ASSERT_FALSE(fake_.abandoned(recreate_));
  server_->stop();
  int destroys = 0;
  for (int i = destroy_of(id, 0, 0); i >= 0; i = destroy_of(id, i + 1, 0)) ++destroys;
  EXPECT_EQ(destroys, 1);
}

// A server stopped while Janus has not answered a session's first create:
// Janus may carry it out after it answered the stop's destroy "none", so
// the mountpoint stays listed, for the next start to destroy.
TEST_F(FakeBroadcast, AStopWhileACreateIsUnansweredKeepsItListed) {
  hold_first_create_ = true;
  holding_ = false;
  // Sent by hand: its answer never comes (the server stops meanwhile).
  const int client = caustic::testing::raw_connect(server_->port());
  ASSERT_GE(client, 0);
  ASSERT_TRUE(caustic::testing::raw_send(
      client, caustic::testing::request_text("POST", "/api/v1/sessions", "Content-Type: application/json\r\n",
                                             R"({"scene": "lens", "mode": "broadcast"})")));
  const int create = fake_.wait_for(0, [](const json& q) { return q.value("request", "") == "create"; });
  ASSERT_GE(create, 0);
  const std::uint64_t id = fake_.request(create).value("id", std::uint64_t{0});
  ASSERT_TRUE(listed().count(id)) << "a create is listed before it is sent";
  server_->stop();
  ::close(client);
  ASSERT_GE(destroy_of(id, 0, 0), 0) << "the stop did not destroy the create on its way";
  EXPECT_TRUE(listed().count(id)) << "Janus said it has none before its create: it may make it still";
}

// Janus hands out ports in turn and gives RTCP the next one only when it is
// free: past a wrap of its range, a port held elsewhere splits a pair, and
// the stream (RTCP on the port after RTP) could not use it. That mountpoint
// is destroyed and another asked for; the session starts on it.
TEST_F(FakeBroadcast, APortPairThatJanusSplitIsAskedForAgain) {
  split_creates_ = 1;
  holding_ = false;
  const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
  EXPECT_EQ(r.status, 201u) << r.body;
  const auto ids = first_creates();
  ASSERT_EQ(ids.size(), 2u) << "one create for the split pair, one for the session's";
  EXPECT_NE(ids[0], ids[1]);
  EXPECT_GE(destroy_of(ids[0], 0), 0) << "the mountpoint with the split pair stays in Janus";
  EXPECT_LT(destroy_of(ids[1], 0, 0), 0) << "the session's own mountpoint was destroyed";
}

// A Janus that splits every pair (its range nearly full) is asked three
// times, each mountpoint destroyed, and the client told.
TEST_F(FakeBroadcast, AJanusThatSplitsEveryPairIsReportedAfterThreeCreates) {
  split_creates_ = 100;
  holding_ = false;
  const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
  EXPECT_EQ(r.status, 502u) << r.body;
  EXPECT_NE(r.body.find("unusable ports"), std::string::npos) << r.body;
  const auto ids = first_creates();
  ASSERT_EQ(ids.size(), 3u);
  for (const std::uint64_t id : ids) EXPECT_GE(destroy_of(id, 0), 0) << "mountpoint " << id << " stays in Janus";
}

// A Janus that will not destroy a stray (here it refuses; one frozen never
// answers) is asked at every check for a minute, then every 10 s: it may
// still hold the mountpoint, which stays listed meanwhile, so a server
// killed then leaves it to its next start. Once Janus says it is gone, unlisted.
TEST_F(FakeBroadcast, AStrayThatJanusKeepsRefusingStaysListedAndIsAskedLessOften) {
  lost_ = false;
  holding_ = false;
  refuse_destroys_ = true;
  const auto r = http("POST", server_->url() + "/api/v1/sessions", R"({"scene": "lens", "mode": "broadcast"})");
  ASSERT_EQ(r.status, 201u) << r.body;
  const auto ids = first_creates();
  ASSERT_EQ(ids.size(), 1u);
  const std::uint64_t id = ids[0];
  end_session(r.json().value("id", ""), r.json().value("token", ""));
  int last = -1;
  for (int n = 0; n < 30; ++n) {
    last = destroy_of(id, static_cast<std::size_t>(last + 1));
    ASSERT_GE(last, 0) << "destroy " << n + 1 << " of the first minute not asked";
  }
  const auto minute = std::chrono::steady_clock::now();
  EXPECT_TRUE(listed().count(id)) << "unlisted while Janus may still hold it";
  const int slow = destroy_of(id, static_cast<std::size_t>(last + 1), 40);
  ASSERT_GE(slow, 0) << "no longer asked after the first minute";
  // Five checks 2 s apart: a loaded machine only lengthens it.
  EXPECT_GE(std::chrono::steady_clock::now() - minute, std::chrono::seconds(6)) << "still asked at every check";
  EXPECT_TRUE(listed().count(id));
  refuse_destroys_ = false;
  const int destroyed_now = destroy_of(id, static_cast<std::size_t>(slow + 1), 40);
  ASSERT_GE(destroyed_now, 0);
  EXPECT_TRUE(unlisted(id)) << "listed after Janus destroyed it";
}
