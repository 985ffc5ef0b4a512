// SPDX-License-Identifier: LGPL-2.1-or-later
#include "readback.hpp"

#include <algorithm>

namespace caustic {

Readback::~Readback() {
  for (auto& s : slots_)
    if (s.fence) glDeleteSync(s.fence);
}

bool Readback::pending() const {
  return host_.queued || std::any_of(slots_.begin(), slots_.end(), [](const Slot& s) { return s.fence != nullptr; });
}

std::size_t Readback::queued_bytes() const {
  if (host_.queued && host_.order == started_) return host_.bytes.size();
  for (const auto& s : slots_)
    if (s.fence && s.order == started_) return static_cast<std::size_t>(s.width) * s.height * s.texel_bytes;
  return 0;
}

void Readback::start(const gl::Texture& texture, std::uint64_t tag, int bytes_per_texel) {
  const std::size_t bytes = static_cast<std::size_t>(texture.width()) * texture.height() * bytes_per_texel;
  if (bytes != capacity_) {
    for (auto& s : slots_) {
      if (s.fence) glDeleteSync(s.fence);
      s = Slot{};
      glNamedBufferStorage(s.buffer.id(), static_cast<GLsizeiptr>(bytes), nullptr, GL_MAP_READ_BIT);
    }
    capacity_ = bytes;
  }
  // Reuse the free slot, or overwrite the older of two unread pictures:
  // only the newest picture matters for a live stream.
  Slot* slot = &slots_[0];
  for (auto& s : slots_)
    if (!s.fence) slot = &s;
  if (slot->fence) {
    slot = slots_[0].order < slots_[1].order ? &slots_[0] : &slots_[1];
    glDeleteSync(slot->fence);
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, slot->buffer.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(texture.id(), 0, bytes_per_texel == 4 ? GL_RGBA : GL_RED, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(bytes), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  slot->fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  slot->tag = tag;
  slot->order = ++started_;
  slot->width = texture.width();
  slot->height = texture.height();
  slot->texel_bytes = bytes_per_texel;
  gl::check_errors("read-back start");
}

void Readback::put(std::vector<std::uint8_t> bytes, std::uint64_t tag) {
  host_ = Host{std::move(bytes), tag, ++started_, true};
}

bool Readback::poll(std::uint8_t* dest, std::size_t bytes, std::uint64_t* tag, bool wait) {
  // The newest finished copy wins; older ones are dropped unread.
  Slot* ready = nullptr;
  for (auto& s : slots_) {
    if (!s.fence || (host_.queued && s.order < host_.order)) continue;
    const GLenum state = glClientWaitSync(s.fence, GL_SYNC_FLUSH_COMMANDS_BIT, wait ? 1'000'000'000 : 0);
    if ((state == GL_ALREADY_SIGNALED || state == GL_CONDITION_SATISFIED) && (!ready || s.order > ready->order))
      ready = &s;
  }
  const std::uint64_t newest = ready ? ready->order : host_.queued ? host_.order : 0;
  if (newest == 0) return false;
  for (auto& s : slots_)
    if (s.fence && s.order <= newest && &s != ready) {
      glDeleteSync(s.fence);
      s.fence = nullptr;
    }
  if (!ready) {
    if (bytes != host_.bytes.size())
      throw EngineError("read-back of " + std::to_string(host_.bytes.size()) + " bytes into " + std::to_string(bytes));
    std::copy(host_.bytes.begin(), host_.bytes.end(), dest);
    host_.queued = false;
    *tag = host_.tag;
    return true;
  }
  if (host_.queued && host_.order < ready->order) host_.queued = false;
  const std::size_t row = static_cast<std::size_t>(ready->width) * ready->texel_bytes;
  if (bytes != row * ready->height)
    throw EngineError("read-back of " + std::to_string(row * ready->height) + " bytes into " + std::to_string(bytes));
  const auto* data = static_cast<const std::uint8_t*>(
      glMapNamedBufferRange(ready->buffer.id(), 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT));
  if (!data) throw EngineError("cannot map the read-back buffer");
  if (ready->texel_bytes == 4) gl::copy_rows_top_first(data, dest, row, ready->height);
  else std::copy_n(data, bytes, dest);
  glUnmapNamedBuffer(ready->buffer.id());
  glDeleteSync(ready->fence);
  ready->fence = nullptr;
  *tag = ready->tag;
  return true;
}

}  // namespace caustic
