// SPDX-License-Identifier: LGPL-2.1-or-later
#include "lingering_close.hpp"

#include <glib-unix.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <fcntl.h>

namespace caustic::server {

LingeringClose::~LingeringClose() {
  for (auto& entry : entries_) release(*entry.second);
}

void LingeringClose::release(Entry& e) {
  if (e.io) g_source_remove(e.io);
  if (e.timer) g_source_remove(e.timer);
  ::close(e.fd);
}

bool LingeringClose::take(int fd) {
  if (entries_.size() >= max_sockets_) return false;
  const int copy = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
  if (copy < 0) return false;
  auto e = std::make_unique<Entry>(Entry{this, copy});
  e->io = g_unix_fd_add(copy, static_cast<GIOCondition>(G_IO_IN | G_IO_HUP | G_IO_ERR), readable, e.get());
  e->timer = g_timeout_add(static_cast<guint>(time_.count()), expired, e.get());
  entries_[copy] = std::move(e);
  return true;
}

gboolean LingeringClose::readable(gint fd, GIOCondition, gpointer data) {
  auto& e = *static_cast<Entry*>(data);
  char sink[16384];
  // A bounded number of reads a wake-up keeps the main loop responsive.
  for (int i = 0; i < 8; ++i) {
    const ssize_t n = ::recv(fd, sink, sizeof sink, MSG_DONTWAIT);
    if (n > 0) {
      e.discarded += static_cast<std::size_t>(n);
      if (e.discarded <= e.owner->max_bytes_) continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
      return G_SOURCE_CONTINUE;
    }
    // The client closed, failed, or sent more than we read: close now.
    e.io = 0;
    e.owner->finish(e);
    return G_SOURCE_REMOVE;
  }
  return G_SOURCE_CONTINUE;
}

gboolean LingeringClose::expired(gpointer data) {
  auto& e = *static_cast<Entry*>(data);
  e.timer = 0;
  e.owner->finish(e);
  return G_SOURCE_REMOVE;
}

void LingeringClose::finish(Entry& e) {
  const int fd = e.fd;
  release(e);
  entries_.erase(fd);  // frees e
}

}  // namespace caustic::server
