// SPDX-License-Identifier: LGPL-2.1-or-later
// A headless OpenGL 4.5 core context through EGL, with no display server.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace caustic {

class GlContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Which EGL platform to open. `automatic` prefers a hardware device
/// (EGL_EXT_platform_device) and falls back to Mesa's surfaceless platform,
/// where llvmpipe renders on the CPU.
enum class EglPlatform { automatic, device, surfaceless };

/// Owns an EGL context (never a window or surface) and makes it current on
/// the thread that calls make_current(). Not copyable; destroy it on the
/// thread that used it last.
class GlContext {
 public:
  /// Creates the context and makes it current. Throws GlContextError with the
  /// reason when no usable EGL display or OpenGL 4.5 core context exists.
  explicit GlContext(EglPlatform platform = EglPlatform::automatic);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  void make_current();
  void release_current();

  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const;
  /// Whether the renderer is Mesa's software one (llvmpipe, softpipe): the
  /// "GPU" is the CPU, and work the CPU does better goes there.
  bool software() const;
  /// GL_VERSION.
  const std::string& version() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Whether a GL_RENDERER names Mesa's software renderers (llvmpipe,
/// softpipe), which run on the CPU and on one thread for their geometry stage.
bool is_software_renderer(const std::string& renderer);

/// Reads CAUSTICD_EGL_PLATFORM (automatic|device|surfaceless); automatic when
/// unset. Throws GlContextError when it, or CAUSTICD_EGL_DEVICE (an integer
/// in [-1, 63]), is set to anything else.
EglPlatform egl_platform_from_environment();

}  // namespace caustic
