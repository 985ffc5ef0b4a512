// SPDX-License-Identifier: LGPL-2.1-or-later
#include "gl_objects.hpp"

#include "caustic/engine.hpp"
#include "shader_sources.hpp"

#include <glm/gtc/type_ptr.hpp>

namespace caustic::gl {

Texture::Texture(GLenum internal_format, int width, int height, GLenum filter)
    : width_(width), height_(height), format_(internal_format) {
  glCreateTextures(GL_TEXTURE_2D, 1, &id_);
  glTextureStorage2D(id_, 1, internal_format, width, height);
  // A one-channel image samples as grey (r, r, r, 1): the post passes,
  // written for colour, read a monochrome frame unchanged.
  if (internal_format == GL_R8 || internal_format == GL_R16F || internal_format == GL_R32F) {
    const GLint grey[] = {GL_RED, GL_RED, GL_RED, GL_ONE};
    glTextureParameteriv(id_, GL_TEXTURE_SWIZZLE_RGBA, grey);
  }
  glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

Texture::~Texture() {
  if (id_) glDeleteTextures(1, &id_);
}

Texture::Texture(Texture&& other) noexcept
    : id_(std::exchange(other.id_, 0)), width_(other.width_), height_(other.height_), format_(other.format_) {}

Texture& Texture::operator=(Texture&& other) noexcept {
  if (this != &other) {
    if (id_) glDeleteTextures(1, &id_);
    id_ = std::exchange(other.id_, 0);
    width_ = other.width_;
    height_ = other.height_;
    format_ = other.format_;
  }
  return *this;
}

RenderTarget::RenderTarget(GLenum internal_format, int width, int height, GLenum filter)
    : texture(internal_format, width, height, filter) {
  glNamedFramebufferTexture(framebuffer.id(), GL_COLOR_ATTACHMENT0, texture.id(), 0);
  if (glCheckNamedFramebufferStatus(framebuffer.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw EngineError("render target " + std::to_string(width) + "x" + std::to_string(height) + " is incomplete");
}

void RenderTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
  glViewport(0, 0, texture.width(), texture.height());
}

Program::Program(const std::vector<Stage>& stages) {
  id_ = glCreateProgram();
  std::vector<GLuint> shaders;
  auto cleanup = [&] {
    for (GLuint s : shaders) glDeleteShader(s);
  };
  for (const auto& stage : stages) {
    std::string text = "#version 450 core\n";
    for (const auto& file : stage.files) {
      auto it = shaders::sources().find(file);
      if (it == shaders::sources().end()) {
        cleanup();
        glDeleteProgram(id_);
        throw EngineError("shader file " + file + " is not embedded");
      }
      text += "#line 1\n";
      text += it->second;
    }
    if (!stage.source.empty()) text += "#line 1\n" + stage.source;
    GLuint shader = glCreateShader(stage.type);
    shaders.push_back(shader);
    const char* src = text.c_str();
    glShaderSource(shader, 1, &src, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[4096];
      glGetShaderInfoLog(shader, sizeof log, nullptr, log);
      cleanup();
      glDeleteProgram(id_);
      throw EngineError("cannot compile " + (stage.source.empty() ? stage.files.back() : std::string("a shader")) +
                        ": " + log);
    }
    glAttachShader(id_, shader);
  }
  glLinkProgram(id_);
  cleanup();
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(id_, sizeof log, nullptr, log);
    glDeleteProgram(id_);
    throw EngineError(std::string("cannot link shader program: ") + log);
  }
}

Program::~Program() { glDeleteProgram(id_); }

void Program::set(const char* name, const glm::mat3& m) const {
  glProgramUniformMatrix3fv(id_, location(name), 1, GL_FALSE, glm::value_ptr(m));
}

void Program::set(const char* name, const glm::mat4& m) const {
  glProgramUniformMatrix4fv(id_, location(name), 1, GL_FALSE, glm::value_ptr(m));
}

void check_errors(const char* where) {
  GLenum first = glGetError();
  if (first == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", first);
  throw EngineError(std::string("OpenGL error ") + code + " in " + where);
}

}  // namespace caustic::gl
