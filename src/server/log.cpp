// SPDX-License-Identifier: LGPL-2.1-or-later
#include "log.hpp"

#include "caustic/server/server.hpp"

#define SD_JOURNAL_SUPPRESS_LOCATION
#include <glib.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <systemd/sd-journal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace caustic::server {
namespace {

std::atomic<int> threshold{static_cast<int>(Level::info)};

// The one table of context fields: journald's name, the text form's.
struct FieldName {
  std::string LogContext::*member;
  const char* journal;
  const char* text;
};
constexpr FieldName kFields[] = {{&LogContext::session, "CAUSTICD_SESSION", "session"},
                                 {&LogContext::scene, "CAUSTICD_SCENE", "scene"},
                                 {&LogContext::codec, "CAUSTICD_CODEC", "codec"},
                                 {&LogContext::peer, "CAUSTICD_PEER", "peer"}};

constexpr const char* kLevelNames[] = {"", "", "", "error", "warning", "notice", "info", "debug"};

enum class Sink { journal, terminal, prefixed };

// systemd sets JOURNAL_STREAM=<device>:<inode> of the stream it connects
// stderr to; only when they match is stderr really the journal (a child
// whose stderr was redirected inherits the variable).
Sink find_sink() {
  if (const char* stream = std::getenv("JOURNAL_STREAM")) {
    unsigned long long dev = 0, ino = 0;
    struct stat st {};
    if (std::sscanf(stream, "%llu:%llu", &dev, &ino) == 2 && fstat(STDERR_FILENO, &st) == 0 &&
        static_cast<unsigned long long>(st.st_dev) == dev && static_cast<unsigned long long>(st.st_ino) == ino)
      return Sink::journal;
  }
  return isatty(STDERR_FILENO) ? Sink::terminal : Sink::prefixed;
}

const Sink sink = find_sink();

void to_journal(Level level, const std::string& message, const LogContext& context) {
  std::vector<std::string> fields{"MESSAGE=" + message,
                                  "PRIORITY=" + std::to_string(static_cast<int>(level)),
                                  "SYSLOG_IDENTIFIER=causticd"};
  for (const auto& f : kFields)
    if (!(context.*f.member).empty()) fields.push_back(std::string(f.journal) + "=" + context.*f.member);
  std::vector<iovec> iov;
  for (auto& f : fields) iov.push_back({f.data(), f.size()});
  if (sd_journal_sendv(iov.data(), static_cast<int>(iov.size())) < 0)
    std::fprintf(stderr, "<%d>%s\n", static_cast<int>(level), message.c_str());
}

GLogWriterOutput library_writer(GLogLevelFlags flags, const GLogField* fields, gsize count, gpointer) {
  std::string domain = "GLib", message;
  for (gsize i = 0; i < count; ++i) {
    const std::string key = fields[i].key;
    const auto* value = static_cast<const char*>(fields[i].value);
    if (!value) continue;
    const std::string text = fields[i].length < 0 ? std::string(value) : std::string(value, fields[i].length);
    if (key == "MESSAGE") message = text;
    if (key == "GLIB_DOMAIN") domain = text;
  }
  // g_debug() and g_info() stay quiet unless G_MESSAGES_DEBUG asks, as GLib's own writer does.
  if ((flags & (G_LOG_LEVEL_DEBUG | G_LOG_LEVEL_INFO)) && !std::getenv("G_MESSAGES_DEBUG")) return G_LOG_WRITER_HANDLED;
  Level level = Level::debug;
  if (flags & (G_LOG_LEVEL_ERROR | G_LOG_LEVEL_CRITICAL)) level = Level::error;
  else if (flags & G_LOG_LEVEL_WARNING) level = Level::warning;
  else if (flags & G_LOG_LEVEL_MESSAGE) level = Level::notice;
  else if (flags & G_LOG_LEVEL_INFO) level = Level::info;
  log(level, domain + ": " + message);
  return G_LOG_WRITER_HANDLED;
}

}  // namespace

void set_log_level(Level level) { threshold = static_cast<int>(level); }

Level level_from_name(const std::string& name) {
  for (int i = static_cast<int>(Level::error); i <= static_cast<int>(Level::debug); ++i)
    if (name == kLevelNames[i]) return static_cast<Level>(i);
  throw std::invalid_argument("unknown log level \"" + name + "\"");
}

void log(Level level, const std::string& message, const LogContext& context) {
  if (static_cast<int>(level) > threshold) return;
  if (sink == Sink::journal) return to_journal(level, message, context);
  // One line, written with one fprintf: lines from several threads do not interleave.
  std::string line = message;
  for (auto& ch : line)
    if (ch == '\n') ch = ' ';
  std::string suffix;
  for (const auto& f : kFields)
    if (!(context.*f.member).empty()) suffix += std::string(suffix.empty() ? " [" : " ") + f.text + "=" + context.*f.member;
  if (!suffix.empty()) suffix += "]";
  if (sink == Sink::terminal)
    std::fprintf(stderr, "causticd: %s: %s%s\n", kLevelNames[static_cast<int>(level)], line.c_str(), suffix.c_str());
  else
    std::fprintf(stderr, "<%d>%s%s\n", static_cast<int>(level), line.c_str(), suffix.c_str());
}

void route_library_messages() { g_log_set_writer_func(library_writer, nullptr, nullptr); }

}  // namespace caustic::server
