// SPDX-License-Identifier: LGPL-2.1-or-later
// Designs when the state directory cannot take them: a full filesystem
// refuses the upload with 507 and keeps nothing of it, a design whose own
// files find no room fails saying so (not blaming the picture), a file
// size limit counts as no room, and a read-only state directory answers 503. The server runs in a mount
// namespace of its own over a small tmpfs, so no disk of this machine
// fills; skipped where that cannot be made (not root, no unshare).
// Black box against `causticd serve` on loopback; every wait bounded.
#include "design_api_support.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <memory>

using namespace caustic::testing::design_api;

namespace {

// Run by `sh -c` with the state directory as $0 and the server as "$@".
constexpr const char* kTmpfs = "mount -t tmpfs -o size=4m tmpfs \"$0\" && exec \"$@\"";
constexpr const char* kReadOnly = "mount -t tmpfs -o ro,size=4m tmpfs \"$0\" && exec \"$@\"";

std::vector<std::string> in_namespace(const char* script, const fs::path& state) {
  return {"unshare", "--mount", "--propagation", "private", "sh", "-c", script, state.string()};
}

bool private_mounts_work() {
  TempDir probe;
  std::vector<std::string> args = in_namespace(kTmpfs, probe.path);
  args.push_back("true");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  gint status = -1;
  const bool ran = g_spawn_sync(nullptr, argv.data(), nullptr,
                                GSpawnFlags(G_SPAWN_SEARCH_PATH | G_SPAWN_STDOUT_TO_DEV_NULL | G_SPAWN_STDERR_TO_DEV_NULL),
                                nullptr, nullptr, nullptr, nullptr, &status, nullptr);
  return ran && g_spawn_check_wait_status(status, nullptr);
}

std::unique_ptr<ServerProcess> server_in(const char* script, const TempDir& state) {
  return std::make_unique<ServerProcess>(small_designs(state), std::vector<std::pair<std::string, std::string>>{},
                                         CAUSTICD_BINARY, in_namespace(script, state.path));
}

// The state directory as the server sees it: /proc/<pid>/root resolves
// paths in the server's mount namespace (sh and unshare exec it: one pid).
fs::path seen(const ServerProcess& server, const TempDir& state) {
  return fs::path("/proc") / server.pid() / "root" / state.path.relative_path();
}

// Fills the filesystem of `dir` until a write fails for want of room (at
// most 8 MiB, twice the tmpfs). False when it never did.
bool fill(const fs::path& dir) {
  const int fd = ::open((dir / "fill").c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  if (fd < 0) return false;
  const std::string block(65536, 'x');
  int error = 0;
  for (int i = 0; i < 128 && !error; ++i)
    if (::write(fd, block.data(), block.size()) < 0) error = errno;
  ::close(fd);
  return error == ENOSPC;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class DesignDisk : public DesignApi {
 protected:
  void SetUp() override {
    DesignApi::SetUp();
    if (IsSkipped()) return;
    if (!private_mounts_work()) GTEST_SKIP() << "no private mount namespace with a tmpfs here (needs root and unshare)";
  }
};

}  // namespace

TEST_F(DesignDisk, AnUploadTheDiskHasNoRoomForIsRefused507AndLeavesNothing) {
  // A small picture fits a write buffer: its write failed only at the
  // close, unchecked, and the upload was taken (202) as an empty file
  // that the design then blamed ("is empty").
  TempDir state;
  const auto server = server_in(kTmpfs, state);
  ASSERT_FALSE(server->url().empty());
  const fs::path dir = seen(*server, state);
  ASSERT_TRUE(fs::is_directory(dir / "designs"));
  ASSERT_TRUE(fill(dir));
  const Response refused = upload(*server, square_png());
  expect_problem(refused, 507, "no room");
  // The visitor learns there is no room, never where.
  EXPECT_EQ(refused.body.find(state.path.string()), std::string::npos) << refused.body;
  EXPECT_EQ(refused.json().value("detail", "").find('/'), std::string::npos) << refused.body;
  EXPECT_EQ(names_in(dir / "designs"), std::vector<std::string>{});
  // With room again the next picture is taken and designed.
  fs::remove(dir / "fill");
  const Response taken = upload(*server, square_png());
  ASSERT_EQ(taken.status, 202u) << taken.body;
  EXPECT_EQ(wait_design(*server, taken.json().value("id", "")).value("state", ""), "ready");
}

TEST_F(DesignDisk, ADesignWhoseFilesFindNoRoomFailsSayingSoAndKeepsNoHalfFiles) {
  // Room for the picture and its meta.json (a page each), none for the
  // face (about a megabyte at 128 cells a side).
  TempDir state;
  const auto server = server_in(kTmpfs, state);
  ASSERT_FALSE(server->url().empty());
  const fs::path dir = seen(*server, state);
  ASSERT_TRUE(fill(dir));
  fs::resize_file(dir / "fill", fs::file_size(dir / "fill") - 65536);
  const Response taken = upload(*server, square_png());
  ASSERT_EQ(taken.status, 202u) << taken.body;
  const std::string id = taken.json().value("id", "");
  const json done = wait_design(*server, id);
  ASSERT_EQ(done.value("state", ""), "failed") << done.dump();
  const std::string error = done.value("error", "");
  EXPECT_NE(error.find("no room to store this design"), std::string::npos) << error;
  EXPECT_EQ(error.find('/'), std::string::npos) << error;
  // Its failure is kept for its owner; nothing the design began writing is.
  EXPECT_EQ(names_in(dir / "designs" / id), (std::vector<std::string>{"error.txt", "meta.json"}));
}

TEST_F(DesignApi, AFileSizeLimitIsNoRoomEither) {
  // An operator's LimitFSIZE= (SIGXFSZ is ignored, so a write past it fails
  // with EFBIG): the picture cannot be stored, and the visitor is told so.
  gchar* prlimit = g_find_program_in_path("prlimit");
  if (!prlimit) GTEST_SKIP() << "no prlimit here";
  g_free(prlimit);
  TempDir state;
  ServerProcess server(small_designs(state), {}, CAUSTICD_BINARY, {"prlimit", "--fsize=64"});
  ASSERT_FALSE(server.url().empty());
  expect_problem(upload(server, square_png()), 507, "no room");
  EXPECT_EQ(names_in(state.path / "designs"), std::vector<std::string>{});
}

TEST_F(DesignDisk, AReadOnlyStateDirectoryAnswersUploads503) {
  // Designs are off (logged at the start) while the gallery streams: a
  // fault the operator mends, not a feature the server lacks (501).
  TempDir state;
  const auto server = server_in(kReadOnly, state);
  ASSERT_FALSE(server->url().empty());
  expect_problem(upload(*server, square_png()), 503, "cannot store designs");
  EXPECT_EQ(http("GET", server->url() + "/api/v1/scenes").status, 200u);
}
