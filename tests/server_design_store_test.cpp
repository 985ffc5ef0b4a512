// SPDX-License-Identifier: LGPL-2.1-or-later
// Designs kept in the state folder across restarts: restored, expired
// unless kept, deleted by their owner alone; one design's broken files
// skip it alone; a design not read back is failed for that run only; a
// stop mid-design designs it again at the next start, and one once its
// files are whole leaves only its read-back to that start.
// Black box against `causticd serve` on loopback; every wait bounded.
#include "design_api_support.hpp"

#include <sys/stat.h>

#include <fstream>
#include <limits>

using namespace caustic::testing::design_api;

TEST_F(DesignApi, DesignsSurviveARestartExpireUnlessKeptAndTheirOwnerMayDeleteThem) {
  TempDir state;
  std::string kept, plain, deleted, token;
  {
    ServerProcess server(small_designs(state));
    for (std::string* id : {&kept, &plain, &deleted}) {
      const json ticket = upload(server, square_png()).json();
      *id = ticket["id"];
      if (id == &deleted) token = ticket["token"];
      ASSERT_EQ(wait_design(server, *id).value("state", ""), "ready");
    }
    // Only the token that came with the upload deletes it.
    const std::string url = server.url() + "/api/v1/designs/" + deleted;
    expect_problem(http("DELETE", url, "", "", {{"Authorization", "Bearer 0123456789abcdef0123456789abcdef"}}), 401);
    EXPECT_EQ(http("DELETE", url, "", "", bearer_token(token)).status, 204u);
    expect_problem(http("GET", url), 404);
    EXPECT_FALSE(fs::exists(state.path / "designs" / deleted));
  }
  {
    ServerProcess server(small_designs(state));
    const json restored = wait_design(server, plain);
    EXPECT_EQ(restored.value("state", ""), "ready") << restored.dump();
    // Restored designs answer at once; the scene itself is read back when a
    // session first asks for it (503 with Retry-After meanwhile).
    EXPECT_EQ(create_session_retrying(server, plain).status, 201u);
  }
  std::ofstream(state.path / "designs" / kept / "keep") << "";
  auto args = small_designs(state);
  args.insert(args.end(), {"--set", "design_expiry_s=1"});
  ServerProcess server(args);
  EXPECT_EQ(wait_design(server, kept).value("state", ""), "ready");
  EXPECT_TRUE(http("GET", server.url() + "/api/v1/designs/" + kept).json()["expires"].is_null());
  expect_problem(http("GET", server.url() + "/api/v1/designs/" + plain), 404);
  EXPECT_FALSE(fs::exists(state.path / "designs" / plain));
}

TEST_F(DesignApi, ADesignDeletedWhileItIsDesignedStaysDeletedAfterAKill) {
  // Deleted while a worker ran it, the design kept its folder until the
  // worker ended; a server killed before then designed it again at its
  // next start, the visitor's picture with it. Bounded: a minute's wait.
  TempDir state;
  std::string id;
  {
    ServerProcess server({"--set", "state_dir=" + state.path.string(), "--set", "design_resolution=1024"});
    const json ticket = upload(server, square_png(1024)).json();
    id = ticket.value("id", "");
    ASSERT_FALSE(id.empty()) << ticket.dump();
    const std::string url = server.url() + "/api/v1/designs/" + id;
    ASSERT_TRUE(wait_designing(server, id));
    EXPECT_EQ(http("DELETE", url, "", "", bearer_token(ticket["token"])).status, 204u);
    server.signal(SIGKILL);
    EXPECT_EQ(server.wait_exit(10000), -1);  // killed: no exit status
  }
  ServerProcess server(small_designs(state));
  expect_problem(http("GET", server.url() + "/api/v1/designs/" + id), 404);
  EXPECT_FALSE(fs::exists(state.path / "designs" / id));
}

TEST_F(DesignApi, ADesignDeletedWhileItIsDesignedStopsThereAndFreesItsPlace) {
  // Deleted while it ran, a design once ran to its end for no one, and the
  // queue counted it free meanwhile. The oracle is order, not time: with a
  // queue of one the next upload is taken only once the deleted design has
  // unwound (its folder gone), and that design never wrote its face.
  TempDir state;
  ServerProcess server({"--set", "state_dir=" + state.path.string(), "--set", "design_resolution=1024", "--set",
                        "design_queue=1", "--set", "design_uploads_per_hour=1000"});
  const json ticket = upload(server, square_png(1024)).json();
  const std::string id = ticket.value("id", "");
  ASSERT_FALSE(id.empty()) << ticket.dump();
  const std::string url = server.url() + "/api/v1/designs/" + id;
  ASSERT_TRUE(wait_designing(server, id));
  const fs::path folder = state.path / "designs" / id;
  EXPECT_EQ(http("DELETE", url, "", "", bearer_token(ticket["token"])).status, 204u);
  bool face_written = false, folder_at_acceptance = true;
  std::string next;
  int refused = 0;
  for (int i = 0; i < 1200 && next.empty(); ++i) {
    face_written = face_written || fs::exists(folder / "face.obj");
    const Response r = upload(server, square_png(128));
    if (r.status == 202u) {
      next = r.json().value("id", "");
      // Asked after the answer: taken means the folder had gone before.
      folder_at_acceptance = fs::exists(folder);
    } else {
      ASSERT_EQ(r.status, 503u) << r.body;
      ++refused;
      g_usleep(50000);
    }
  }
  ASSERT_FALSE(next.empty()) << "the queue stayed full after its one design was deleted";
  EXPECT_FALSE(folder_at_acceptance) << "a new upload was taken while the deleted design still held the worker";
  EXPECT_FALSE(face_written) << "the deleted design ran on to its face";
  EXPECT_FALSE(fs::exists(folder));
  std::printf("upload refused %d times while the deleted design unwound\n", refused);
  std::string next_state;
  for (int i = 0; i < 600 && next_state != "designing" && next_state != "ready"; ++i) {
    next_state = http("GET", server.url() + "/api/v1/designs/" + next).json().value("state", "");
    if (next_state != "designing") g_usleep(100000);
  }
  EXPECT_TRUE(next_state == "designing" || next_state == "ready") << next_state;
}

TEST_F(DesignApi, OneDesignsBrokenFilesSkipThatDesignAlone) {
  TempDir state;
  const std::string good = stored_design(state);
  ASSERT_NE(good, "");
  // Copies of it, each broken as a disk or a hand can break one. Once a
  // pipe held the start for good, a link to /dev/zero took gigabytes, a
  // wrong type or a looping link turned every design off, and a time past
  // the clock's range expired (and removed) its design.
  const fs::path designs = state.path / "designs";
  const auto copy = [&](char digit) {
    const fs::path to = designs / std::string(32, digit);
    fs::copy(designs / good, to, fs::copy_options::recursive);
    return to;
  };
  const fs::path pipe = copy('a'), zero = copy('b'), typed = copy('c'), future = copy('d');
  fs::remove(pipe / "meta.json");
  ASSERT_EQ(::mkfifo((pipe / "meta.json").c_str(), 0600), 0);
  fs::remove(zero / "thumbnail.png");
  fs::create_symlink("/dev/zero", zero / "thumbnail.png");
  std::ofstream(typed / "report.json") << R"({"resolution": "x"})";
  json meta = json::parse(std::ifstream(future / "meta.json"));
  meta["created"] = std::numeric_limits<std::int64_t>::max();
  std::ofstream(future / "meta.json") << meta.dump();
  fs::create_symlink(designs / std::string(32, 'e'), designs / std::string(32, 'e'));  // a link to itself
  ServerProcess server(small_designs(state));
  EXPECT_EQ(wait_design(server, good).value("state", ""), "ready") << "designs went off for one broken design";
  EXPECT_EQ(upload(server, square_png()).status, 202u);
  for (const fs::path& broken : {pipe, future})
    expect_problem(http("GET", server.url() + "/api/v1/designs/" + broken.filename().string()), 404);
  EXPECT_TRUE(fs::exists(future / "meta.json")) << "skipped, not removed";
  // The one whose thumbnail was a device started without reading it (the server is up), and answers.
  EXPECT_NE(http("GET", server.url() + "/api/v1/designs/" + zero.filename().string()).status, 0u);
}

TEST_F(DesignApi, ADesignNotReadBackIsFailedForThatRunOnly) {
  // A design whose face cannot be read at a start (a disk gone bad for a
  // while, no GL for a moment) was once marked failed for good.
  TempDir state;
  const std::string id = stored_design(state);
  ASSERT_NE(id, "");
  const fs::path dir = state.path / "designs" / id;
  // Without what answers need, the design is read back at the start.
  fs::remove(dir / "info.json");
  fs::rename(dir / "face.obj", dir / "face.obj.away");
  {
    ServerProcess server(small_designs(state));
    const json failed = wait_design(server, id);
    EXPECT_EQ(failed.value("state", ""), "failed") << failed.dump();
    EXPECT_NE(failed.value("error", "").find("tries again when it restarts"), std::string::npos) << failed.dump();
  }
  EXPECT_FALSE(fs::exists(dir / "error.txt"));
  fs::rename(dir / "face.obj.away", dir / "face.obj");
  ServerProcess server(small_designs(state));
  EXPECT_EQ(wait_design(server, id).value("state", ""), "ready");
  EXPECT_EQ(create_session_retrying(server, id).status, 201u);
}

TEST_F(DesignApi, AStopOnceADesignsFilesAreWholeLeavesItsReadBackToTheNextStart) {
  // Stopped while a design was stored, the server read the design back
  // (built and drew its scene: seconds at 1024^2) before it exited. Its
  // files are whole then, and the next start restores it: the stop now
  // leaves the read-back, whose thumbnail is the sign, to that start.
  TempDir state;
  std::string id;
  {
    ServerProcess server({"--set", "state_dir=" + state.path.string(), "--set", "design_resolution=1024"});
    id = upload(server, square_png(1024)).json().value("id", "");
    ASSERT_FALSE(id.empty());
    std::string stage;
    for (int i = 0; i < 6000 && stage != "storing"; ++i) {
      const json now = http("GET", server.url() + "/api/v1/designs/" + id).json();
      ASSERT_NE(now.value("state", ""), "ready") << "the stage of storing was never seen";
      stage = now.value("stage", "");
      if (stage != "storing") g_usleep(20000);
    }
    ASSERT_EQ(stage, "storing");
    server.signal(SIGTERM);
    EXPECT_EQ(server.wait_exit(120000), 0);
  }
  const fs::path dir = state.path / "designs" / id;
  EXPECT_TRUE(fs::exists(dir / "report.json")) << "the design's files were not whole";
  EXPECT_FALSE(fs::exists(dir / "thumbnail.png")) << "the stop waited for the design to be read back";
  ServerProcess server({"--set", "state_dir=" + state.path.string()});
  EXPECT_EQ(wait_design(server, id).value("state", ""), "ready");
  EXPECT_TRUE(fs::exists(dir / "thumbnail.png"));
}

TEST_F(DesignApi, AStopMidDesignExitsCleanlyAndTheNextStartDesignsItAgain) {
  // A stop in the designer's steps unwinds the design at its next step: the
  // server exits 0 and keeps the picture, and the next start designs it.
  TempDir state;
  std::string id;
  {
    ServerProcess server({"--set", "state_dir=" + state.path.string(), "--set", "design_resolution=1024"});
    id = upload(server, square_png(1024)).json().value("id", "");
    ASSERT_FALSE(id.empty());
    ASSERT_TRUE(wait_designing(server, id));
    server.signal(SIGTERM);
    EXPECT_EQ(server.wait_exit(120000), 0);
  }
  const fs::path dir = state.path / "designs" / id;
  EXPECT_FALSE(fs::exists(dir / "report.json")) << "the design ran on to its end";
  EXPECT_TRUE(fs::exists(dir / "picture.png"));
  ServerProcess server(small_designs(state));
  EXPECT_EQ(wait_design(server, id).value("state", ""), "ready");
  EXPECT_FALSE(fs::exists(dir / "picture.png")) << "the visitor's picture is not kept once designed";
}
