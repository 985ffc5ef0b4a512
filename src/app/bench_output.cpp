// SPDX-License-Identifier: LGPL-2.1-or-later
// Where every bench writes: its --out folder, tried before the frames are
// timed (a bench runs minutes; a folder found unwritable after them lost the
// figures), and gnuplot run inside it without a shell, so a folder name with
// quotes or spaces is only a name.
#include "perf_bench.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <system_error>

namespace caustic::app {

bool bench_folder_ready(const std::filesystem::path& out) {
  const auto refuse = [&](const std::string& why) {
    std::cerr << "causticd bench: --out " << out.string() << ": " << why << "\n";
    return false;
  };
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) return refuse("cannot be made a folder (" + ec.message() + ")");
  if (!std::filesystem::is_directory(out, ec)) return refuse("is not a folder");
  // A file made and removed: the folder takes new files.
  std::string probe = (out / ".causticd-bench-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return refuse(std::string("cannot be written (") + std::strerror(errno) + ")");
  ::close(fd);
  std::filesystem::remove(probe, ec);
  return true;
}

bool run_gnuplot(const std::filesystem::path& folder, const char* script, const char* log) {
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec.
    if (::chdir(folder.c_str()) != 0) ::_exit(127);
    const int fd = ::open(log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) ::dup2(fd, STDERR_FILENO);
    ::execlp("gnuplot", "gnuplot", script, static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace caustic::app
