// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/gl_context.hpp"

#define EGL_EGLEXT_PROTOTYPES 0
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include "gl_objects.hpp"

#include <cstdlib>
#include <cstring>
#include <vector>

namespace caustic {
namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t len = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += len)
    if ((p == list || p[-1] == ' ') && (p[len] == ' ' || p[len] == '\0')) return true;
  return false;
}

std::string egl_error_text() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04x", eglGetError());
  return buf;
}

// CAUSTICD_EGL_DEVICE: which hardware device (0, 1, ...) to use; -1: the first.
int wanted_device() {
  const char* value = std::getenv("CAUSTICD_EGL_DEVICE");
  if (!value || !*value) return -1;
  char* end = nullptr;
  const long n = std::strtol(value, &end, 10);
  if (*end || n < -1 || n > 63)
    throw GlContextError(std::string("CAUSTICD_EGL_DEVICE must be an integer in [-1, 63], got \"") + value + "\"");
  return static_cast<int>(n);
}

// The wanted EGL device that is not a software renderer (the first without
// CAUSTICD_EGL_DEVICE), if the driver lists any.
EGLDisplay hardware_device_display() {
  const int wanted = wanted_device();
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_extension(client_ext, "EGL_EXT_device_enumeration") || !has_extension(client_ext, "EGL_EXT_platform_device"))
    return EGL_NO_DISPLAY;
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_device_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (!query_devices || !query_device_string) return EGL_NO_DISPLAY;
  EGLint count = 0;
  if (!query_devices(0, nullptr, &count) || count <= 0) return EGL_NO_DISPLAY;
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  query_devices(count, devices.data(), &count);
  int hardware = 0;
  for (EGLint i = 0; i < count; ++i) {
    const char* ext = query_device_string(devices[i], EGL_EXTENSIONS);
    if (has_extension(ext, "EGL_MESA_device_software")) continue;
    if (wanted >= 0 && hardware++ != wanted) continue;
    EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    if (display != EGL_NO_DISPLAY) return display;
  }
  if (wanted >= 0)
    throw GlContextError("GPU " + std::to_string(wanted) + " not found: EGL lists " + std::to_string(hardware) +
                         (hardware == 1 ? " hardware device" : " hardware devices") +
                         (hardware > 0 ? " (0 .. " + std::to_string(hardware - 1) + ")" : std::string()));
  return EGL_NO_DISPLAY;
}

}  // namespace

struct GlContext::State {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string renderer;
  std::string version;
};

namespace {

EglPlatform platform_named() {
  const char* value = std::getenv("CAUSTICD_EGL_PLATFORM");
  if (!value || !*value || std::strcmp(value, "automatic") == 0) return EglPlatform::automatic;
  if (std::strcmp(value, "device") == 0) return EglPlatform::device;
  if (std::strcmp(value, "surfaceless") == 0) return EglPlatform::surfaceless;
  throw GlContextError(std::string("CAUSTICD_EGL_PLATFORM must be automatic, device or surfaceless, got \"") +
                       value + "\"");
}

}  // namespace

EglPlatform egl_platform_from_environment() {
  (void)wanted_device();  // CAUSTICD_EGL_DEVICE checked too, before a context is wanted
  return platform_named();
}

GlContext::GlContext(EglPlatform platform) : state_(std::make_unique<State>()) {
  EGLDisplay display = EGL_NO_DISPLAY;
  if (platform != EglPlatform::surfaceless) display = hardware_device_display();
  if (display == EGL_NO_DISPLAY && platform != EglPlatform::surfaceless && wanted_device() >= 0)
    throw GlContextError("GPU " + std::to_string(wanted_device()) + " not found: EGL lists no hardware device");
  if (display == EGL_NO_DISPLAY && platform == EglPlatform::device)
    throw GlContextError("no hardware EGL device found (EGL_EXT_platform_device)");
  if (display == EGL_NO_DISPLAY) {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client_ext, "EGL_MESA_platform_surfaceless"))
      throw GlContextError("EGL offers neither a GPU device nor Mesa's surfaceless platform; install libegl-mesa0 and "
                           "libgl1-mesa-dri");
    display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  }
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    throw GlContextError("cannot initialise an EGL display: " + egl_error_text());
  // The display is deliberately never terminated: EGL displays are shared by
  // every context of the process, and eglTerminate would pull it from under
  // other sessions' contexts.
  state_->display = display;
  if (!eglBindAPI(EGL_OPENGL_API)) throw GlContextError("EGL cannot bind the OpenGL API: " + egl_error_text());
  const char* display_ext = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(display_ext, "EGL_KHR_surfaceless_context"))
    throw GlContextError("EGL display lacks EGL_KHR_surfaceless_context");

  EGLConfig config = nullptr;
  if (!has_extension(display_ext, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &n) || n < 1)
      throw GlContextError("no EGL config supports OpenGL: " + egl_error_text());
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  state_->context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (state_->context == EGL_NO_CONTEXT)
    throw GlContextError("cannot create an OpenGL 4.5 core context (" + egl_error_text() +
                         "); the renderer needs OpenGL 4.5");
  make_current();
  state_->renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  state_->version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

GlContext::~GlContext() {
  if (state_->context != EGL_NO_CONTEXT) {
    eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(state_->display, state_->context);
  }
  eglReleaseThread();
}

void GlContext::make_current() {
  if (!eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context))
    throw GlContextError("cannot make the EGL context current: " + egl_error_text());
}

void GlContext::release_current() { eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

const std::string& GlContext::renderer() const { return state_->renderer; }

bool GlContext::software() const { return is_software_renderer(state_->renderer); }

bool is_software_renderer(const std::string& renderer) {
  return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
}
const std::string& GlContext::version() const { return state_->version; }

}  // namespace caustic
