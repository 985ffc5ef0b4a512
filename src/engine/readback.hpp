// SPDX-License-Identifier: LGPL-2.1-or-later
// Asynchronous read-back of the tone-mapped picture through two pixel
// buffer objects: start() queues the copy and returns; poll() hands the
// picture over once its fence has signalled, so a streaming thread never
// waits for the GPU (on a GPU the copy overlaps the next frame; on llvmpipe
// the fence is already signalled when start() returns). A picture the CPU
// made (cpu_post.hpp) joins the same queue, so the newest still wins.
#pragma once

#include "caustic/engine.hpp"
#include "gl_objects.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace caustic {

class Readback {
 public:
  Readback() = default;
  ~Readback();
  Readback(const Readback&) = delete;
  Readback& operator=(const Readback&) = delete;

  /// Queues a copy of `texture` tagged with `tag`: RGBA8 (rows turned top
  /// first on the way out) or, with `bytes_per_texel` 1, an R8 texture whose
  /// rows are already in memory order (the I420 layout).
  void start(const gl::Texture& texture, std::uint64_t tag, int bytes_per_texel = 4);
  /// Queues a picture the CPU already made (`bytes`, in the order poll()
  /// delivers: RGBA rows from the top, or I420), ready at once.
  void put(std::vector<std::uint8_t> bytes, std::uint64_t tag);
  /// Copies the newest finished picture into `dest` (exactly `bytes` long:
  /// its one copy on the way out of GL), once ready or after waiting when
  /// `wait`. Returns false when none is ready; `tag` is what start() got.
  /// Throws EngineError when `bytes` is not the picture's size.
  bool poll(std::uint8_t* dest, std::size_t bytes, std::uint64_t* tag, bool wait);
  /// The size in bytes of what poll() will deliver next (0: nothing queued).
  std::size_t queued_bytes() const;
  bool pending() const;

 private:
  struct Slot {
    gl::Buffer buffer;
    GLsync fence = nullptr;
    std::uint64_t tag = 0;
    std::uint64_t order = 0;
    int width = 0, height = 0;
    int texel_bytes = 4;
  };
  struct Host {  // a picture made on the CPU
    std::vector<std::uint8_t> bytes;
    std::uint64_t tag = 0;
    std::uint64_t order = 0;
    bool queued = false;
  };
  std::array<Slot, 2> slots_;
  Host host_;
  std::uint64_t started_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace caustic
