// SPDX-License-Identifier: LGPL-2.1-or-later
// RAII owners for OpenGL object names and a checked shader program. Every GL
// object the engine creates is held by one of these, so an exception on the
// way never leaks GPU memory.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace caustic::gl {

enum class Kind { buffer, texture, framebuffer, vertex_array };

/// One GL object name of the given kind, deleted with its owner.
template <Kind K>
class Object {
 public:
  Object() {
    if constexpr (K == Kind::buffer) glCreateBuffers(1, &id_);
    if constexpr (K == Kind::texture) static_assert(K != Kind::texture, "textures need a target: use Texture");
    if constexpr (K == Kind::framebuffer) glCreateFramebuffers(1, &id_);
    if constexpr (K == Kind::vertex_array) glCreateVertexArrays(1, &id_);
  }
  ~Object() { reset(); }
  Object(Object&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Object& operator=(Object&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  GLuint id() const { return id_; }

 private:
  void reset() {
    if (!id_) return;
    if constexpr (K == Kind::buffer) glDeleteBuffers(1, &id_);
    if constexpr (K == Kind::framebuffer) glDeleteFramebuffers(1, &id_);
    if constexpr (K == Kind::vertex_array) glDeleteVertexArrays(1, &id_);
    id_ = 0;
  }
  GLuint id_ = 0;
};

using Buffer = Object<Kind::buffer>;
using Framebuffer = Object<Kind::framebuffer>;
using VertexArray = Object<Kind::vertex_array>;

/// A 2D texture with immutable storage.
class Texture {
 public:
  Texture() = default;
  Texture(GLenum internal_format, int width, int height, GLenum filter = GL_NEAREST);
  ~Texture();
  Texture(Texture&& other) noexcept;
  Texture& operator=(Texture&& other) noexcept;
  Texture(const Texture&) = delete;
  Texture& operator=(const Texture&) = delete;
  GLuint id() const { return id_; }
  int width() const { return width_; }
  int height() const { return height_; }
  GLenum format() const { return format_; }

 private:
  GLuint id_ = 0;
  int width_ = 0, height_ = 0;
  GLenum format_ = 0;
};

/// A texture with a framebuffer that renders into it.
struct RenderTarget {
  Texture texture;
  Framebuffer framebuffer;
  RenderTarget() = default;
  RenderTarget(GLenum internal_format, int width, int height, GLenum filter = GL_NEAREST);
  void bind() const;  // binds for drawing and sets the viewport
};

/// A linked program from named shader sources (see shader_sources.hpp); each
/// stage is "#version 450 core" + optional library files + the stage file.
class Program {
 public:
  struct Stage {
    GLenum type;
    std::vector<std::string> files;  // embedded shader files, concatenated in order
    std::string source = {};         // appended after the files (tests bring their own kernels)
  };
  explicit Program(const std::vector<Stage>& stages);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;
  GLuint id() const { return id_; }
  void use() const { glUseProgram(id_); }

  void set(const char* name, float v) const { glProgramUniform1f(id_, location(name), v); }
  void set(const char* name, int v) const { glProgramUniform1i(id_, location(name), v); }
  void set(const char* name, bool v) const { glProgramUniform1i(id_, location(name), v ? 1 : 0); }
  void set(const char* name, const glm::vec2& v) const { glProgramUniform2f(id_, location(name), v.x, v.y); }
  void set(const char* name, const glm::ivec2& v) const { glProgramUniform2i(id_, location(name), v.x, v.y); }
  void set(const char* name, const glm::vec3& v) const { glProgramUniform3f(id_, location(name), v.x, v.y, v.z); }
  void set(const char* name, const glm::mat3& m) const;
  void set(const char* name, const glm::mat4& m) const;

 private:
  GLint location(const char* name) const { return glGetUniformLocation(id_, name); }
  GLuint id_ = 0;
};

/// Copies `height` rows of `row` elements from GL's bottom-row-first order
/// into `top_first`, the order every image of this project uses.
template <typename T>
void copy_rows_top_first(const T* bottom_first, T* top_first, std::size_t row, int height) {
  for (int y = 0; y < height; ++y)
    std::copy_n(bottom_first + static_cast<std::size_t>(height - 1 - y) * row, row,
                top_first + static_cast<std::size_t>(y) * row);
}

/// Throws EngineError when glGetError reports anything, naming `where`.
void check_errors(const char* where);

}  // namespace caustic::gl
