// SPDX-License-Identifier: LGPL-2.1-or-later
// Preloaded into causticd by tools/sanitize.sh tsan: tells ThreadSanitizer
// about the hand-overs it cannot see. Debian's GLib implements GMutex,
// GRWLock and GCond on bare futexes and GStreamer counts its references
// with atomics, all in code built without TSan, so a buffer, message or
// object that one thread fills and hands to another through a queue's
// mutex or a last unref reads as a race. GObject, GIO, libgstreamer and
// the plugins call GLib (and plugins libgstreamer) through their PLTs, so
// definitions preloaded here come first; each calls the library's own and
// marks the happens-before edge with TSan's annotation interface.
//
// Conventions: a lock acquires the lock's address, an unlock releases it;
// g_cond_wait releases its mutex while it sleeps and acquires it again. An
// unref releases then acquires the object's address, so the thread that
// drops the last reference (and frees) has seen every earlier holder's
// writes: the acquire runs on every unref, not only the last, which can
// hide a race between two holders' writes made before their unrefs (a
// false negative, never a false report). Not seen: what GLib does inside
// itself (the GAsyncQueue under a GThreadPool), calls inside libgstreamer
// (linked -Bsymbolic-functions) and GstAtomicQueue's lock-free hand-over
// of bus messages, which the bus watch below stands in for.
#include <dlfcn.h>
#include <glib.h>

extern "C" {
void __tsan_acquire(void* addr);
void __tsan_release(void* addr);
}

namespace {

// GLib's and GObject's constructors take locks before TSan's runtime is
// set up (nothing orders their initialisers after it): until this file's
// own constructor has run, after TSan's (a library it links), the process
// has one thread and nothing to annotate. Built without -fsanitize=thread
// for the same reason: an instrumented entry would touch the runtime.
bool tsan_ready = false;
__attribute__((constructor)) void on_load() { tsan_ready = true; }

void acquire(void* addr) {
  if (tsan_ready) __tsan_acquire(addr);
}
void release(void* addr) {
  if (tsan_ready) __tsan_release(addr);
}

// GLib's definition of `name`, looked up once (the preload comes first).
template <typename F>
F real(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) g_error("tsan_glib_sync: %s not found", name);
  return reinterpret_cast<F>(f);
}

#define REAL(name) static const auto real_##name = real<decltype(&name)>(#name)

}  // namespace

extern "C" {

void g_mutex_lock(GMutex* m) {
  REAL(g_mutex_lock);
  real_g_mutex_lock(m);
  acquire(m);
}
gboolean g_mutex_trylock(GMutex* m) {
  REAL(g_mutex_trylock);
  if (!real_g_mutex_trylock(m)) return FALSE;
  acquire(m);
  return TRUE;
}
void g_mutex_unlock(GMutex* m) {
  REAL(g_mutex_unlock);
  release(m);
  real_g_mutex_unlock(m);
}

void g_rec_mutex_lock(GRecMutex* m) {
  REAL(g_rec_mutex_lock);
  real_g_rec_mutex_lock(m);
  acquire(m);
}
gboolean g_rec_mutex_trylock(GRecMutex* m) {
  REAL(g_rec_mutex_trylock);
  if (!real_g_rec_mutex_trylock(m)) return FALSE;
  acquire(m);
  return TRUE;
}
void g_rec_mutex_unlock(GRecMutex* m) {
  REAL(g_rec_mutex_unlock);
  release(m);
  real_g_rec_mutex_unlock(m);
}

void g_rw_lock_writer_lock(GRWLock* l) {
  REAL(g_rw_lock_writer_lock);
  real_g_rw_lock_writer_lock(l);
  acquire(l);
}
gboolean g_rw_lock_writer_trylock(GRWLock* l) {
  REAL(g_rw_lock_writer_trylock);
  if (!real_g_rw_lock_writer_trylock(l)) return FALSE;
  acquire(l);
  return TRUE;
}
void g_rw_lock_writer_unlock(GRWLock* l) {
  REAL(g_rw_lock_writer_unlock);
  release(l);
  real_g_rw_lock_writer_unlock(l);
}
void g_rw_lock_reader_lock(GRWLock* l) {
  REAL(g_rw_lock_reader_lock);
  real_g_rw_lock_reader_lock(l);
  acquire(l);
}
gboolean g_rw_lock_reader_trylock(GRWLock* l) {
  REAL(g_rw_lock_reader_trylock);
  if (!real_g_rw_lock_reader_trylock(l)) return FALSE;
  acquire(l);
  return TRUE;
}
void g_rw_lock_reader_unlock(GRWLock* l) {
  REAL(g_rw_lock_reader_unlock);
  release(l);
  real_g_rw_lock_reader_unlock(l);
}

void g_cond_wait(GCond* c, GMutex* m) {
  REAL(g_cond_wait);
  release(m);
  real_g_cond_wait(c, m);
  acquire(m);
}
gboolean g_cond_wait_until(GCond* c, GMutex* m, gint64 end_time) {
  REAL(g_cond_wait_until);
  release(m);
  const gboolean signalled = real_g_cond_wait_until(c, m, end_time);
  acquire(m);
  return signalled;
}

// Freeing acquires what was released at the block's address (an unref, a
// bus watch done with its message): the free that follows a last unref
// made inside a library, out of reach of the wrappers here, still comes
// after every holder's release. An address nothing released costs a lookup.
void g_free(gpointer mem) {
  REAL(g_free);
  if (mem) acquire(mem);
  real_g_free(mem);
}
void g_slice_free1(gsize size, gpointer mem) {
  REAL(g_slice_free1);
  if (mem) acquire(mem);
  real_g_slice_free1(size, mem);
}

void g_object_unref(gpointer object) {
  REAL(g_object_unref);
  release(object);
  acquire(object);
  real_g_object_unref(object);
}

}  // extern "C"

// GStreamer's, declared here rather than through its headers (the preload
// needs only the symbols): a mini object is a buffer, event, message, query,
// caps or sample.
extern "C" void gst_mini_object_unref(void* object) {
  static const auto real_unref = real<void (*)(void*)>("gst_mini_object_unref");
  release(object);
  acquire(object);
  real_unref(object);
}

// A bus watch's messages come through GstAtomicQueue, lock-free: the watch
// acquires each message before its function reads it and releases it after,
// so that the thread that drops the message's last reference later has
// seen the read.
namespace {
using BusFunc = gboolean (*)(void* bus, void* message, gpointer data);
struct Watch {
  BusFunc func;
  gpointer data;
  GDestroyNotify notify;
};
gboolean watch_message(void* bus, void* message, gpointer p) {
  const Watch* w = static_cast<const Watch*>(p);
  acquire(message);
  const gboolean keep = w->func(bus, message, w->data);
  release(message);
  return keep;
}
void watch_gone(gpointer p) {
  const Watch* w = static_cast<const Watch*>(p);
  if (w->notify) w->notify(w->data);
  delete w;
}
}  // namespace

extern "C" guint gst_bus_add_watch_full(void* bus, gint priority, BusFunc func, gpointer data,
                                        GDestroyNotify notify) {
  static const auto real_add = real<guint (*)(void*, gint, BusFunc, gpointer, GDestroyNotify)>("gst_bus_add_watch_full");
  return real_add(bus, priority, watch_message, new Watch{func, data, notify}, watch_gone);
}
