// Asynchronous read-back of the tone-mapped picture through two pixel
// buffer objects: start() queues the copy and returns; poll() hands the
// picture over once its fence has signalled, so a streaming thread never
// waits for the GPU (on a GPU the copy overlaps the next frame; on llvmpipe
// the fence is already signalled when start() returns).
#pragma once

#include "caustic/engine.hpp"
#include "gl_objects.hpp"

#include <array>
#include <cstdint>

namespace caustic {

class Readback {
 public:
  Readback() = default;
  ~Readback();
  Readback(const Readback&) = delete;
  Readback& operator=(const Readback&) = delete;

  /// Queues a copy of `texture` (RGBA8) tagged with `tag`.
  void start(const gl::Texture& texture, std::uint64_t tag);
  /// The oldest queued copy, once ready (or after waiting when `wait`).
  /// Returns false when none is ready; `tag` is what start() was given.
  bool poll(Rgba8Image* out, std::uint64_t* tag, bool wait);
  bool pending() const;

 private:
  struct Slot {
    gl::Buffer buffer;
    GLsync fence = nullptr;
    std::uint64_t tag = 0;
    std::uint64_t order = 0;
    int width = 0, height = 0;
  };
  std::array<Slot, 2> slots_;
  std::uint64_t started_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace caustic
