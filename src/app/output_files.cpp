// SPDX-License-Identifier: LGPL-2.1-or-later
// Where the commands' files go: each output is tried before the work (a
// render or a design of minutes found unwritable after it lost it), then
// written under a hidden name beside its own and renamed over it once every
// output is complete, so a reader never sees half a file and a failure, or
// an interruption (Ctrl-C, a service stop), leaves none behind.
#include "commands.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <system_error>

namespace caustic::app {

namespace {

/// The file a write to `out` replaces: the one a link names (a plain write
/// goes through a link, and the link stays), also one still to be made,
/// else `out` itself. Empty with `ec` set for a link that cannot be
/// followed (a loop, an unreadable folder on its way).
std::filesystem::path written_place(const std::filesystem::path& out, std::error_code& ec) {
  ec.clear();
  std::filesystem::path place = out;
  // Links are followed by hand: weakly_canonical keeps a link whose file is
  // missing as it is, and O_EXCL then fails on the link.
  for (int hops = 0;; ++hops) {
    const auto status = std::filesystem::symlink_status(place, ec);
    if (status.type() == std::filesystem::file_type::not_found) ec.clear();  // a file to be made
    if (ec || status.type() != std::filesystem::file_type::symlink) break;
    if (hops == 40) {
      ec = std::make_error_code(std::errc::too_many_symbolic_link_levels);
      return {};
    }
    const auto target = std::filesystem::read_symlink(place, ec);
    if (ec) return {};
    place = target.is_absolute() ? target : place.parent_path() / target;
  }
  if (ec) return {};
  return place == out ? out : std::filesystem::weakly_canonical(place, ec);
}

// The temporaries of the write in progress, for a signal handler to remove:
// plain buffers filled before the count that publishes them, since a
// handler may only read memory and call async-signal-safe functions.
char (*pending_names)[PATH_MAX] = nullptr;
volatile std::sig_atomic_t pending_count = 0;
constexpr int stop_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

extern "C" void remove_pending_and_stop(int sig) {
  for (std::sig_atomic_t i = 0; i < pending_count; ++i) ::unlink(pending_names[i]);
  // Ends as the signal would have without the handler, so a shell or a
  // service manager sees what stopped the command.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

/// Holds the stop signals' handlers while temporaries exist; the handlers
/// the process had before come back at the end.
class PendingTemporaries {
 public:
  explicit PendingTemporaries(std::size_t count) : names_(new char[count][PATH_MAX]), capacity_(count) {
    pending_names = names_.get();
    pending_count = 0;
    struct sigaction action {};
    action.sa_handler = remove_pending_and_stop;
    sigemptyset(&action.sa_mask);
    // A signal the process was started ignoring (nohup, a background job
    // of a shell) stays ignored: the handler would make it stop the command.
    for (std::size_t i = 0; i < std::size(stop_signals); ++i) {
      ::sigaction(stop_signals[i], nullptr, &saved_[i]);
      if (saved_[i].sa_handler != SIG_IGN) ::sigaction(stop_signals[i], &action, nullptr);
    }
  }
  ~PendingTemporaries() {
    pending_count = 0;
    for (std::size_t i = 0; i < std::size(stop_signals); ++i) ::sigaction(stop_signals[i], &saved_[i], nullptr);
    pending_names = nullptr;
  }
  PendingTemporaries(const PendingTemporaries&) = delete;
  PendingTemporaries& operator=(const PendingTemporaries&) = delete;

  void add(const std::filesystem::path& temporary) {
    added_last_ = false;
    if (static_cast<std::size_t>(pending_count) >= capacity_ || temporary.native().size() >= PATH_MAX) return;
    std::memcpy(names_[pending_count], temporary.c_str(), temporary.native().size() + 1);
    std::atomic_signal_fence(std::memory_order_release);
    pending_count = pending_count + 1;
    added_last_ = true;
  }
  void drop_last() {
    if (added_last_) pending_count = pending_count - 1;
    added_last_ = false;
  }

 private:
  std::unique_ptr<char[][PATH_MAX]> names_;
  std::size_t capacity_;
  bool added_last_ = false;
  struct sigaction saved_[std::size(stop_signals)] {};
};

}  // namespace

bool output_writable(const char* command, const std::filesystem::path& out, const char* flag,
                     const std::vector<std::filesystem::path>& inputs) {
  const auto dir = std::filesystem::absolute(out).parent_path();
  const auto refuse = [&](const std::string& why) {
    std::cerr << "causticd " << command << ": " << flag << " " << out.string() << ": " << why << "\n";
    return false;
  };
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return refuse("folder " + dir.string() + " does not exist");
  if (std::filesystem::is_directory(out, ec)) return refuse("is a folder");
  // Tried where the write goes: through a link, also one whose file is
  // still to be made (O_EXCL on the link itself would find it there).
  const auto place = written_place(out, ec);
  if (ec) return refuse("is a link that cannot be followed (" + ec.message() + ")");
  const bool existed = std::filesystem::exists(place, ec);
  // A device or a pipe would be replaced by a file (written under another
  // name, then renamed over it), and an input overwritten by an output.
  if (existed && !std::filesystem::is_regular_file(place, ec))
    return refuse("is not a regular file (a device, a pipe or a socket): give a file's name");
  for (const auto& in : inputs)
    if (existed && std::filesystem::equivalent(place, in, ec))
      return refuse("is the command's input " + in.string() + ": it would be overwritten");
  // Tried before the work rather than found after it: a file there is
  // opened for writing (and left as it was), a new one made and removed.
  const int fd = ::open(place.c_str(), O_WRONLY | (existed ? 0 : O_CREAT | O_EXCL) | O_CLOEXEC | O_NONBLOCK, 0644);
  if (fd < 0) return refuse(std::string("cannot be written (") + std::strerror(errno) + ")");
  ::close(fd);
  if (!existed) std::filesystem::remove(place, ec);
  // The folder of the file replaced must take a new one too, though the
  // file there may be written in place.
  std::string probe = (std::filesystem::absolute(place, ec).parent_path() / ".causticd-XXXXXX").string();
  const int made = ::mkstemp(probe.data());
  if (made < 0)
    return refuse("its folder takes no new file (" + std::string(std::strerror(errno)) +
                  "), and the file is written beside its name, then renamed over it");
  ::close(made);
  ::unlink(probe.c_str());
  return true;
}

void write_complete(const std::vector<std::filesystem::path>& outputs,
                    const std::function<void(const std::filesystem::path&, const std::filesystem::path&)>& write) {
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> written;  // temporary, final
  PendingTemporaries pending(outputs.size());
  try {
    for (const auto& out : outputs) {
      std::error_code ec;
      const auto place = written_place(out, ec);
      if (ec) throw std::runtime_error("cannot follow the link " + out.string() + ": " + ec.message());
      // Made here (O_EXCL, so never another file) with the umask's mode
      // that the final file would have had.
      for (int attempt = 0;; ++attempt) {
        const auto temporary = place.parent_path() / ("." + place.stem().string() + "." + std::to_string(::getpid()) +
                                                      "-" + std::to_string(attempt) + out.extension().string());
        // Listed before it exists, so no signal finds it made and unlisted
        // (an unlink of a name not made does nothing).
        pending.add(temporary);
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) pending.drop_last();
        if (fd >= 0) {
          ::close(fd);
          written.emplace_back(temporary, place);
          break;
        }
        if (errno != EEXIST || attempt == 100)
          throw std::runtime_error("cannot write beside " + out.string() + ": " + std::strerror(errno));
      }
      try {
        write(out, written.back().first);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        // Said of the file the user named, not of the temporary one.
        std::string what = e.what();
        const std::string temporary = written.back().first.string(), named = out.string();
        for (auto at = what.find(temporary); at != std::string::npos; at = what.find(temporary, at + named.size()))
          what.replace(at, temporary.size(), named);
        throw std::runtime_error(what);
      }
    }
    for (const auto& [temporary, out] : written) std::filesystem::rename(temporary, out);
  } catch (...) {
    std::error_code ignored;
    for (const auto& [temporary, out] : written) std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(errno));
  const bool whole = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  int error = whole ? 0 : errno;
  // The close may be the first to say there was no room.
  if (std::fclose(f) != 0 && !error) error = errno;
  if (!whole || error) throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(error ? error : EIO));
}

void write_text_files(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<std::filesystem::path> names;
  for (const auto& [name, text] : files) names.push_back(name);
  std::size_t next = 0;  // write_complete writes them in the order given
  write_complete(names, [&](const std::filesystem::path&, const std::filesystem::path& temporary) {
    write_text(temporary, files[next++].second);
  });
}

}  // namespace caustic::app
