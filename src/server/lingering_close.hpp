// SPDX-License-Identifier: LGPL-2.1-or-later
// Closing a socket while its client is still sending makes the kernel answer
// with a reset, and a reset can destroy an answer already sent before the
// client reads it: a 413 refused at the head of a large upload reached the
// client as "broken pipe". Like a web server's lingering close, the listener
// hands such a socket (its write side shut) to LingeringClose, which reads
// and discards what still arrives until the client closes, or for at most
// `time` and `max_bytes`, and only then closes it. At most `max_sockets` at
// once: beyond that a socket closes at once, as before.
#pragma once

#include <glib.h>

#include <chrono>
#include <cstddef>
#include <map>
#include <memory>

namespace caustic::server {

class LingeringClose {
 public:
  LingeringClose(std::size_t max_sockets, std::chrono::milliseconds time, std::size_t max_bytes)
      : max_sockets_(max_sockets), time_(time), max_bytes_(max_bytes) {}
  ~LingeringClose();  // closes every socket still lingering
  LingeringClose(const LingeringClose&) = delete;
  LingeringClose& operator=(const LingeringClose&) = delete;

  /// Takes a duplicate of `fd`, so the caller closes its own as usual; false
  /// (nothing taken) when `max_sockets` linger already or dup() fails.
  bool take(int fd);

 private:
  struct Entry {
    LingeringClose* owner;
    int fd;
    guint io = 0, timer = 0;
    std::size_t discarded = 0;
  };
  static gboolean readable(gint fd, GIOCondition, gpointer data);
  static gboolean expired(gpointer data);
  static void release(Entry& e);  // its sources removed, its socket closed
  void finish(Entry& e);          // released and forgotten

  std::size_t max_sockets_;
  std::chrono::milliseconds time_;
  std::size_t max_bytes_;
  std::map<int, std::unique_ptr<Entry>> entries_;  // by duplicate fd
};

}  // namespace caustic::server
