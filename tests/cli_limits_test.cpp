// SPDX-License-Identifier: LGPL-2.1-or-later
// The commands at the machine's limits and the file system's edges: a size
// the memory cannot hold is refused before the work, memory that runs out
// all the same is said, a write that fails or is interrupted leaves no
// file, and a link named as an output is written through.
#include "causticd_runner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <csignal>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

class CliLimits : public CliTest {};

}  // namespace

// A frame larger than the memory the process can have is refused before it
// is rendered, naming the size as it was set and what it needs, where an
// allocation failed midway (exit 1) or the OOM killer ended the command. A
// data limit stands in for a small machine: 8192 x 8192 in colour needs 6 GB.
TEST_F(CliLimits, AFrameLargerThanTheMemoryIsRefusedBeforeItIsRendered) {
  const std::string limited = "prlimit --data=" + std::to_string(1024 << 20);
  const fs::path png = dir_ / "big.png", exr = dir_ / "big.exr";
  const CommandResult colour = causticd_with_env(
      limited, "render --scene " + scene("prism") + " -o " + png.string() + " --width 8192 --height 8192");
  EXPECT_EQ(colour.status, 2) << colour.output;
  EXPECT_NE(colour.output.find("--width 8192 --height 8192: a colour frame of 8192x8192 needs about 6."),
            std::string::npos)
      << colour.output;
  // The data limit, unless the machine or its cgroup has even less to give.
  EXPECT_TRUE(colour.output.find("(its data limit, RLIMIT_DATA)") != std::string::npos ||
              colour.output.find("MemAvailable") != std::string::npos ||
              colour.output.find("its cgroup's") != std::string::npos)
      << colour.output;
  const CommandResult grey = causticd_with_env(limited, "render --scene " + scene("slab") + " -o " + png.string() +
                                                            " --set render.width=8192 --set render.height=8192");
  EXPECT_EQ(grey.status, 2) << grey.output;
  EXPECT_NE(grey.output.find("render.width 8192 render.height 8192: a grey frame of 8192x8192 needs about 2."),
            std::string::npos)
      << grey.output;
  // The tracer's image is a thread's each.
  const CommandResult traced = causticd_with_env(limited, "reference --scene " + scene("slab") + " -o " + exr.string() +
                                                              " --set render.width=8192 --set render.height=8192 "
                                                              "--threads 1 --photons 1000");
  EXPECT_EQ(traced.status, 2) << traced.output;
  EXPECT_NE(traced.output.find("render.width 8192 render.height 8192 on 1 thread: a grey image"), std::string::npos)
      << traced.output;
  // So is a calibration's largest frame beside its reference.
  const CommandResult calibrated =
      causticd_with_env(limited, "calibrate --scene " + scene("prism") + " -o " + (dir_ / "c.json").string() +
                                     " --max-side 4096 --photons 1000 --frames 1");
  EXPECT_EQ(calibrated.status, 2) << calibrated.output;
  EXPECT_NE(calibrated.output.find("--max-side 4096: a colour frame of 4096x"), std::string::npos) << calibrated.output;
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(exr));
  EXPECT_FALSE(fs::exists(dir_ / "c.json"));
  // What fits is rendered under the same limit.
  const CommandResult small = causticd_with_env(
      limited, "render --scene " + scene("prism") + " -o " + png.string() + " --width 512 --height 512");
  EXPECT_EQ(small.status, 0) << small.output;
}

// Memory, threads or a library's device refused while the scene's levels
// are built threw past the command (terminate: SIGABRT and a core). Under a
// ladder of data limits the command exits, whatever it could do. Limits
// below these fail in the libraries' own start-up, before main.
TEST_F(CliLimits, ACommandShortOfMemoryExitsWithAMessageNotAnAbort) {
  for (int mib = 128; mib <= 320; mib += 32) {
    const CommandResult r = causticd_with_env("prlimit --data=" + std::to_string(mib << 20),
                                              "render --scene " + scene("lens") + " -o " + (dir_ / "x.png").string() +
                                                  " --width 16 --height 16");
    EXPECT_TRUE(r.status == 0 || r.status == 1 || r.status == 2) << mib << " MiB: " << r.status << "\n" << r.output;
    EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << mib << " MiB: " << r.output;
    if (r.status == 1) {
      EXPECT_NE(r.output.find("causticd render: "), std::string::npos) << r.output;
    }
  }
}

// A write that fails (a full disk, here a file size limit, which once ended
// the process by SIGXFSZ) leaves no truncated file and no file of the set.
TEST_F(CliLimits, AWriteThatFailsLeavesNoFileBehind) {
  const std::string limited = "prlimit --fsize=200000";
  for (const std::string& args : {"render --scene " + scene("wavy") + " -o " + (dir_ / "w.png").string() + " -o " +
                                      (dir_ / "w.exr").string() + " --width 1024 --height 1024",
                                  "reference --scene " + scene("wavy") + " -o " + (dir_ / "r.exr").string() +
                                      " --set render.width=1024 --set render.height=1024 --photons 1000000"}) {
    const CommandResult r = causticd_with_env(limited, args);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("cannot write " + dir_.string() + "/"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(dir_)) << r.output;
  }
}

// A bench's table, collected as it runs and written at its end: a write
// that fails is said (exit 1, naming the file) where the bench said it wrote
// the table and left it cut short, and no part of it is left.
TEST_F(CliLimits, ABenchWhoseTableCannotBeWrittenSaysSo) {
  const CommandResult r = causticd_with_env(
      "prlimit --fsize=100", "bench --perf --out " + dir_.string() + " --frames 1 --meshes 16 32 --sizes 128");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("causticd bench: cannot write " + (dir_ / "perf.csv").string() + ": File too large"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("wrote "), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(dir_)) << r.output;
}

// Stopped while it writes (Ctrl-C; SIGTERM from a service manager is
// handled alike), a command removes the hidden files its outputs were being
// written under and ends by the signal, as a shell or a supervisor expects.
// The temporaries are watched for, and the signal sent when one appears;
// four large outputs keep the write long enough to be caught.
TEST_F(CliLimits, AStopWhileWritingLeavesNoTemporaryBehind) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // A child of a test that ignores SIGINT would too (dispositions survive exec).
    ::signal(SIGINT, SIG_DFL);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
    const std::string out = (dir_ / "a").string();
    ::execl(CAUSTICD_BINARY, CAUSTICD_BINARY, "render", "--scene", scene("wavy").c_str(), "-o", (out + ".png").c_str(),
            "-o", (out + "b.png").c_str(), "-o", (out + ".exr").c_str(), "-o", (out + "b.exr").c_str(), "--width",
            "2048", "--height", "2048", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const std::string temporary = ".a." + std::to_string(pid) + "-";
  const auto hidden = [&](const std::string& prefix) {
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename().string().rfind(prefix, 0) == 0) return true;
    return false;
  };
  bool sent = false, reaped = false;
  int status = 0;
  // Bounded: the render takes seconds, ten minutes is a machine in trouble.
  for (int polls = 0; polls < 600'000 && !sent && !reaped; ++polls) {
    reaped = ::waitpid(pid, &status, WNOHANG) == pid;
    if (!reaped && hidden(temporary)) sent = ::kill(pid, SIGINT) == 0;
    if (!sent) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!sent && !reaped) ::kill(pid, SIGKILL);
  if (!reaped) ::waitpid(pid, &status, 0);
  ASSERT_TRUE(sent) << "the write ended before a temporary was seen (status " << status << ")";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
  EXPECT_FALSE(hidden(".")) << "a hidden file is left in " << dir_;
}

// An output that is a link: the file it names gets the picture and the
// link stays (the picture written beside it and renamed over it would
// otherwise have replaced the link with a file of its own).
TEST_F(CliLimits, AnOutputThatIsALinkIsWrittenThrough) {
  fs::create_directories(dir_ / "real");
  std::ofstream(dir_ / "real" / "r.png") << "old";
  fs::create_symlink("real/r.png", dir_ / "l.png");
  const CommandResult r = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "l.png").string() +
                                   " --width 32 --height 32");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(dir_ / "l.png"));
  EXPECT_GT(fs::file_size(dir_ / "real" / "r.png"), 100u) << r.output;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "real"), fs::directory_iterator()), 1) << "no temporary left";
  // A link whose file is still to be made gets it made, as a plain write
  // would (O_EXCL on the link itself once refused it as existing); links in
  // a loop are said as such.
  fs::create_symlink("real/new.png", dir_ / "n.png");
  const CommandResult made = causticd("render --scene " + scene("slab") + " -o " + (dir_ / "n.png").string() +
                                      " --width 32 --height 32");
  EXPECT_EQ(made.status, 0) << made.output;
  EXPECT_TRUE(fs::is_symlink(dir_ / "n.png"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "real" / "new.png")) << made.output;
  fs::create_symlink("b.png", dir_ / "a.png");
  fs::create_symlink("a.png", dir_ / "b.png");
  expect_rejected("render --scene " + scene("slab") + " -o " + (dir_ / "a.png").string(),
                  "--output " + (dir_ / "a.png").string() + ": is a link that cannot be followed (Too many levels");
}

// The memory a cgroup allows is a bound too (v1's memory.limit_in_bytes or
// v2's memory.max, at any level): a child cgroup of this one, limited to
// 1 GiB, holds the command. Where cgroups cannot be made (no root, a
// read-only cgroupfs) there is nothing to try.
TEST_F(CliLimits, AFrameLargerThanTheCgroupAllowsIsRefused) {
  std::ifstream self("/proc/self/cgroup");
  fs::path dir, limit;
  for (std::string line; std::getline(self, line);) {
    const auto path = line.substr(line.find(':', line.find(':') + 1) + 1);
    if (line.rfind("0::", 0) == 0 && fs::exists("/sys/fs/cgroup/cgroup.controllers"))
      dir = fs::path("/sys/fs/cgroup" + path), limit = "memory.max";
    else if (line.find(":memory:") != std::string::npos)
      dir = fs::path("/sys/fs/cgroup/memory" + path), limit = "memory.limit_in_bytes";
    if (!dir.empty() && line.find(":memory:") != std::string::npos) break;
  }
  const fs::path child = dir / ("causticd_test_" + std::to_string(::getpid()));
  std::error_code ec;
  if (dir.empty() || !fs::create_directory(child, ec)) GTEST_SKIP() << "no cgroup can be made under " << dir;
  const bool limited = static_cast<bool>(std::ofstream(child / limit) << (1 << 30));
  CommandResult r{-1, ""};
  if (limited)
    r = causticd_with_env("sh -c 'echo $$ > " + (child / "cgroup.procs").string() + " && exec \"$0\" \"$@\"'",
                          "render --scene " + scene("prism") + " -o " + (dir_ / "x.png").string() +
                              " --width 8192 --height 8192");
  fs::remove(child, ec);  // empty again once the command has ended
  if (!limited) GTEST_SKIP() << "no memory limit can be set in " << child;
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("this process can have about 1.0 GB (its cgroup's " + limit.string()), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// A file the user may write in a folder that takes no new file: written
// beside its name and renamed, it failed after the frame was rendered; it
// is refused before. Root writes anywhere, so it runs as nobody there,
// with a copy of the scene: a checkout in root's home (mode 0700) is out
// of nobody's reach, and its scene was "File does not exist".
TEST_F(CliLimits, AnOutputWhoseFolderTakesNoNewFileIsRefusedBeforeTheWork) {
  const fs::path folder = dir_ / "read-only", png = folder / "x.png";
  fs::create_directories(folder);
  fs::create_directories(dir_ / "scenes");
  fs::create_directories(dir_ / "meshes");
  const fs::path slab = dir_ / "scenes" / "slab.json";
  fs::copy_file(scene("slab"), slab);
  fs::copy_file(fs::path(scene("slab")).parent_path() / ".." / "meshes" / "slab.obj", dir_ / "meshes" / "slab.obj");
  std::ofstream(png) << "old";
  fs::permissions(png, fs::perms::all & ~(fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec));
  fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                              fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const std::string as_nobody = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups" : "";
  const CommandResult r = causticd_with_env(
      as_nobody, "render --scene " + slab.string() + " -o " + png.string() + " --width 32 --height 32");
  fs::permissions(folder, fs::perms::owner_all);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--output " + png.string() + ": its folder takes no new file"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("renderer:"), std::string::npos) << "refused before a context: " << r.output;
}

// The tracer runs at most a thread a core (each keeps an image): more
// asked is said, naming the flag, rather than quietly taken down.
TEST_F(CliLimits, MoreThreadsThanCoresAreSaid) {
  const CommandResult r = causticd("reference --scene " + scene("slab") + " -o " + (dir_ / "r.exr").string() +
                                   " --set render.width=32 --set render.height=32 --photons 1000 --threads 1024");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: --threads 1024: this machine has "), std::string::npos) << r.output;
  const CommandResult one = causticd("reference --scene " + scene("slab") + " -o " + (dir_ / "r.exr").string() +
                                     " --set render.width=32 --set render.height=32 --photons 1000 --threads 1");
  EXPECT_EQ(one.output.find("warning"), std::string::npos) << one.output;
}
