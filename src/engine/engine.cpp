// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"

#include "cpu_post.hpp"
#include "passes.hpp"
#include "readback.hpp"

#include "caustic/light_grid.hpp"
#include "caustic/receivers.hpp"
#include "caustic/spectral.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

namespace caustic {
namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// Everything but post-processing decides the caustic pass.
bool same_caustic(const Scene& a, const Scene& b) {
  return a.object == b.object && a.light == b.light && a.screen == b.screen && a.receivers == b.receivers &&
         a.render == b.render;
}

// Mesa's software rasterisers run the geometry stage on one thread.
bool software_renderer() {
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return is_software_renderer(name ? name : "");
}

}  // namespace


struct Engine::Impl {
  RayPass ray;
  PostPass post;
  CpuPost cpu_post;
  bool picture_on_cpu = false;  // the last frame's picture is cpu_post's, not ldr's
  gl::RenderTarget hdr, ldr, i420;
  gl::Program to_i420{{{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"i420.frag"}}}};
  gl::VertexArray empty_vao;
  Readback readback;
  std::optional<Scene> scene;
  std::shared_ptr<const Mesh> mesh;
  Placement placement;
  std::unique_ptr<Solid> solid;  // object.shape "solid": its mesh in Embree, posed
  bool ray_dirty = false, post_dirty = false;
  bool prepare_dirty = false;  // the local base and the meter need the new HDR image or settings
  bool snap_exposure = true;   // a new mesh or size: no smoothing from the last scene's exposure
  double target_exposure = 1, shown_exposure = 1;
  std::chrono::steady_clock::time_point last_post{};
  int divisor = 1;  // preview: caustic at 1/divisor of the output size
  bool still = false;  // left standing: full spectral frames take render.still_wavelengths
  const bool software = software_renderer();
  TriangleSetup setup = TriangleSetup::automatic;
  FrameStats stats;
  std::uint64_t ray_passes = 0;
};

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;

void Engine::set_scene(const Scene& scene, std::shared_ptr<const Mesh> mesh, bool moved,
                       const std::shared_ptr<const MeshBounds>& placed_by) {
  if (!mesh) throw EngineError("set_scene needs a mesh");
  validate_scene(scene);
  Placement placement = placed_by && placed_by->normal == scene.object.flat_face_normal
                            ? place_object(scene.object, *placed_by)
                            : place_object(scene.object, *mesh);
  check_geometry(scene, *mesh, placement);

  auto& s = *impl_;
  const bool new_mesh = mesh != s.mesh;
  const bool new_size = !s.scene || s.scene->render.width != scene.render.width ||
                        s.scene->render.height != scene.render.height;
  const bool solid = scene.object.shape == Shape::solid;
  if (solid && (new_mesh || !s.solid)) check_closed(*mesh);
  if (new_mesh) s.ray.upload(*mesh);
  // The multipass tracer's Embree scene is posed in the world: rebuilt when
  // the mesh or the pose changes.
  if (!solid) s.solid.reset();
  else if (new_mesh || !s.solid || s.placement.model != placement.model) s.solid = std::make_unique<Solid>(*mesh, placement);
  if (new_size) s.ldr = gl::RenderTarget(GL_RGBA8, scene.render.width, scene.render.height);
  const int hdr_w = std::max(1, scene.render.width / s.divisor), hdr_h = std::max(1, scene.render.height / s.divisor);
  // Linear filtering serves the preview's upsampling; full frames read texels
  // exactly. A spectral frame adds its wavelengths in colour; a tinted face
  // filters its light in colour.
  const GLenum hdr_format = spectral(scene) || tinted(*mesh) ? GL_RGBA32F : GL_R32F;
  const bool new_hdr = s.hdr.texture.width() != hdr_w || s.hdr.texture.height() != hdr_h ||
                       s.hdr.texture.format() != hdr_format;
  if (new_hdr) {
    s.hdr = gl::RenderTarget(hdr_format, hdr_w, hdr_h, GL_LINEAR);
    s.ray.forget_whole_image();
  }
  s.ray_dirty = s.ray_dirty || new_mesh || new_size || new_hdr || !same_caustic(*s.scene, scene);
  s.post_dirty = s.post_dirty || s.ray_dirty || s.scene->post != scene.post;
  s.prepare_dirty = s.prepare_dirty || s.post_dirty;
  s.snap_exposure = s.snap_exposure || (new_mesh && !moved) || new_size;
  s.scene = scene;
  s.mesh = std::move(mesh);
  s.placement = placement;
}

void Engine::set_preview_divisor(int divisor) {
  if (divisor < 1) throw EngineError("preview divisor must be at least 1");
  auto& s = *impl_;
  if (divisor == s.divisor) return;
  s.divisor = divisor;
  if (s.scene) set_scene(*s.scene, s.mesh);  // new caustic target size, dirty frame
}

void Engine::set_still(bool still) {
  auto& s = *impl_;
  if (still == s.still) return;
  const bool changes = s.scene && frame_wavelengths(*s.scene, s.divisor > 1, still) !=
                                      frame_wavelengths(*s.scene, s.divisor > 1, s.still);
  s.still = still;
  if (changes) s.ray_dirty = s.post_dirty = s.prepare_dirty = true;
}

void Engine::set_triangle_setup(TriangleSetup setup) {
  auto& s = *impl_;
  if (setup == s.setup) return;
  s.setup = setup;
  s.ray_dirty = s.post_dirty = s.prepare_dirty = s.scene.has_value();
}

bool Engine::dirty() const { return impl_->ray_dirty || impl_->post_dirty; }

bool Engine::render() {
  auto& s = *impl_;
  if (!s.scene || !dirty()) return false;
  if (s.ray_dirty) {
    const auto start = std::chrono::steady_clock::now();
    s.stats.trace_ms = 0;
    const auto passes = spectral_passes(*s.scene, frame_wavelengths(*s.scene, s.divisor > 1, s.still));
    // A lathe's or mesh's triangles are not in the shaders: its scenes land on the CPU whatever the setup.
    const bool on_cpu = s.setup == TriangleSetup::cpu || (s.setup == TriangleSetup::automatic && s.software) ||
                        has_shaped_receiver(*s.scene);
    s.stats.cpu_setup = on_cpu;
    // One pass: the per-vertex method, or the multipass method for a solid
    // on a light grid that a preview thins like its picture. The CPU's time
    // is the tracing, the setup, the deposit and the image's upload.
    auto pass = [&](double ior, glm::vec3 weight, bool clear, bool count) {
      const auto traced = std::chrono::steady_clock::now();
      if (!s.solid) {
        if (!on_cpu) return s.ray.draw(*s.scene, s.placement, s.hdr, ior, weight, clear, count);
        s.ray.draw_on_cpu(*s.scene, s.placement, *s.mesh, s.hdr, ior, weight, clear, count);
        s.stats.trace_ms += elapsed_ms(traced);
        return;
      }
      const int n = std::max(16, s.scene->render.light_grid / s.divisor);
      const LandedGrid grid = trace_light_grid(*s.scene, *s.solid, ior, n);
      s.stats.trace_ms += elapsed_ms(traced);
      if (count) s.stats.split = static_cast<std::uint32_t>(grid.split);
      s.ray.draw_landed(grid, *s.scene, s.placement, s.hdr, weight, clear, count, on_cpu);
    };
    if (passes.empty()) pass(s.scene->object.ior, glm::vec3(1), true, true);
    for (std::size_t i = 0; i < passes.size(); ++i) {
      const auto& w = passes[i].weight;
      pass(passes[i].ior, glm::vec3(w.r, w.g, w.b), i == 0, i + 1 == passes.size());
    }
    s.ray.settle();
    s.stats.wavelengths = passes.empty() ? 1 : static_cast<int>(passes.size());
    s.stats.colour = s.hdr.texture.format() != GL_R32F;
    const TriangleCounts counts = s.ray.counts();  // the last pass's; waits for it to finish
    glFinish();
    s.stats.ray_ms = elapsed_ms(start);
    s.stats.drawn = counts.drawn;
    s.stats.dropped = counts.dropped;
    s.stats.folded = std::min(counts.positive, counts.negative);
    s.stats.collapsed = counts.collapsed;
    ++s.ray_passes;
  }
  const auto start = std::chrono::steady_clock::now();
  PostParams post = s.scene->post;
  if (s.divisor > 1) post.bloom_strength = 0;  // a preview skips the glow
  const bool automatic = post.exposure_mode == ExposureMode::automatic;
  // A frame the CPU deposited is post-processed where it lies
  // (cpu_post.hpp): the local operator's base stays on the GL.
  const std::vector<float>* on_cpu = post.tone_map == ToneMap::global ? s.ray.whole_image() : nullptr;
  const int channels = s.ray.whole_channels();
  if (!on_cpu) s.ray.upload_whole_image();  // the GL's post-processing reads the texture
  const int hdr_w = s.hdr.texture.width(), hdr_h = s.hdr.texture.height();
  if (s.prepare_dirty) {
    const exposure::Histogram histogram = !on_cpu ? s.post.prepare(post, s.hdr.texture, automatic)
                                          : automatic ? CpuPost::meter(*on_cpu, hdr_w, hdr_h, channels)
                                                      : exposure::Histogram{};
    if (automatic) {
      s.stats.metered = exposure::quantile(histogram, post.auto_percentile);
      // Nothing lit: keep the last exposure rather than jump to an arbitrary one.
      if (s.stats.metered > 0) s.target_exposure = exposure::exposure_for(s.stats.metered, post.gamma);
    }
  }
  const double target = automatic ? s.target_exposure * post.exposure : post.exposure;
  const double dt = std::chrono::duration<double>(start - s.last_post).count();
  s.shown_exposure = s.snap_exposure || !automatic ? target
                                                   : exposure::adapt(s.shown_exposure, target, std::min(dt, 0.5),
                                                                     post.exposure_adapt_s);
  s.snap_exposure = false;
  s.last_post = start;
  // The tiles the caustic pass drew (cpu_setup.cpp, caustic.geom): a glow stops at their edges.
  const auto tiles = atlas_layout(hdr_w, hdr_h, receiving_surfaces(*s.scene).size());
  if (on_cpu) {
    s.cpu_post.run(post, *on_cpu, hdr_w, hdr_h, s.ldr.texture.width(), s.ldr.texture.height(), s.shown_exposure,
                   channels, tiles);
  } else {
    s.post.run(post, s.hdr.texture, s.ldr, s.shown_exposure, tiles);
    glFinish();
  }
  s.picture_on_cpu = on_cpu != nullptr;
  s.stats.cpu_post = s.picture_on_cpu;
  s.stats.exposure = s.shown_exposure;
  s.stats.post_ms = elapsed_ms(start);
  if (!s.ray_dirty) s.stats.ray_ms = 0;
  s.ray_dirty = s.prepare_dirty = false;
  // Still settling towards the metered exposure: the next frame draws again
  // (post-processing only), so a change eases in instead of pumping.
  s.post_dirty = s.shown_exposure != target;
  return true;
}

HdrImage Engine::read_hdr() const {
  const auto& t = impl_->hdr.texture;
  if (t.format() != GL_R32F) return luminance(read_hdr_rgb());
  HdrImage img{t.width(), t.height(), std::vector<float>(static_cast<std::size_t>(t.width()) * t.height())};
  if (img.pixels.empty()) return img;
  const std::vector<float>* whole = impl_->ray.whole_image();  // the CPU's, maybe not uploaded
  if (whole && impl_->ray.whole_channels() == 1) {
    gl::copy_rows_top_first(whole->data(), img.pixels.data(), static_cast<std::size_t>(img.width), img.height);
    return img;
  }
  std::vector<float> raw(img.pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(float)), raw.data());
  gl::check_errors("HDR read-back");
  gl::copy_rows_top_first(raw.data(), img.pixels.data(), static_cast<std::size_t>(img.width), img.height);
  return img;
}

RgbHdrImage Engine::read_hdr_rgb() const {
  const auto& t = impl_->hdr.texture;
  RgbHdrImage img{t.width(), t.height(), std::vector<float>(static_cast<std::size_t>(t.width()) * t.height() * 3)};
  if (img.pixels.empty()) return img;
  if (t.format() == GL_R32F) {  // a grey frame: R = G = B
    const HdrImage grey = read_hdr();
    for (std::size_t i = 0; i < grey.pixels.size(); ++i)
      img.pixels[3 * i] = img.pixels[3 * i + 1] = img.pixels[3 * i + 2] = grey.pixels[i];
    return img;
  }
  std::vector<float> raw(img.pixels.size());
  if (const std::vector<float>* whole = impl_->ray.whole_image()) {  // the CPU's RGBA, maybe not uploaded
    for (std::size_t i = 0; i < raw.size() / 3; ++i)
      for (std::size_t c = 0; c < 3; ++c) raw[3 * i + c] = (*whole)[4 * i + c];
  } else {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t.id(), 0, GL_RGB, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(float)), raw.data());
    gl::check_errors("HDR read-back");
  }
  gl::copy_rows_top_first(raw.data(), img.pixels.data(), static_cast<std::size_t>(img.width) * 3, img.height);
  return img;
}

Rgba8Image Engine::read_ldr() const {
  const auto& t = impl_->ldr.texture;
  if (impl_->picture_on_cpu) return {t.width(), t.height(), impl_->cpu_post.rgba()};
  Rgba8Image img{t.width(), t.height(), std::vector<std::uint8_t>(static_cast<std::size_t>(t.width()) * t.height() * 4)};
  if (img.pixels.empty()) return img;
  std::vector<std::uint8_t> raw(img.pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(raw.size()), raw.data());
  gl::check_errors("LDR read-back");
  gl::copy_rows_top_first(raw.data(), img.pixels.data(), static_cast<std::size_t>(img.width) * 4, img.height);
  return img;
}

std::size_t Engine::picture_bytes(PixelFormat format) const {
  const std::size_t w = impl_->ldr.texture.width(), h = impl_->ldr.texture.height();
  return format == PixelFormat::rgba ? w * h * 4 : w * h * 3 / 2;
}

void Engine::start_readback(std::uint64_t tag, PixelFormat format) {
  auto& s = *impl_;
  const int w = s.ldr.texture.width(), h = s.ldr.texture.height();
  if (format == PixelFormat::i420 && (w % 8 || h % 2))
    throw EngineError("I420 needs a width divisible by 8 and an even height");
  if (s.picture_on_cpu)  // no GL: the CPU's picture, converted where it lies
    return s.readback.put(format == PixelFormat::rgba ? s.cpu_post.rgba() : s.cpu_post.i420(), tag);
  if (format == PixelFormat::rgba) return s.readback.start(s.ldr.texture, tag);
  if (s.i420.texture.width() != w || s.i420.texture.height() != h * 3 / 2)
    s.i420 = gl::RenderTarget(GL_R8, w, h * 3 / 2);
  // One pass writes the three planes in memory order, so the read-back is a
  // straight copy of 1.5 bytes a pixel instead of 4.
  s.i420.bind();
  glDisable(GL_BLEND);
  glBindVertexArray(s.empty_vao.id());
  s.to_i420.use();
  glBindTextureUnit(0, s.ldr.texture.id());
  s.to_i420.set("uPicture", 0);
  s.to_i420.set("uSize", glm::ivec2(w, h));
  if (s.hdr.texture.format() == GL_R32F) {
    // A grey frame's chroma is 128 throughout (the U and V weights sum to
    // zero): the pass draws the Y plane only and the rest is cleared, which
    // on a software renderer takes a quarter off the conversion.
    glViewport(0, 0, w, h);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, h, w, h / 2);
    const float neutral[4] = {128.0f / 255.0f, 0, 0, 0};
    glClearNamedFramebufferfv(s.i420.framebuffer.id(), GL_COLOR, 0, neutral);
    glDisable(GL_SCISSOR_TEST);
    glViewport(0, 0, w, h * 3 / 2);
  } else {
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  gl::check_errors("I420 conversion");
  s.readback.start(s.i420.texture, tag, 1);
}

bool Engine::poll_readback(std::uint8_t* dest, std::size_t bytes, std::uint64_t* tag, bool wait) {
  return impl_->readback.poll(dest, bytes, tag, wait);
}

bool Engine::poll_ldr_readback(Rgba8Image* picture, std::uint64_t* tag, bool wait) {
  const std::size_t bytes = impl_->readback.queued_bytes();
  if (bytes == 0) return false;
  picture->width = impl_->ldr.texture.width();
  picture->height = impl_->ldr.texture.height();
  picture->pixels.resize(bytes);
  return impl_->readback.poll(picture->pixels.data(), bytes, tag, wait);
}

const FrameStats& Engine::stats() const { return impl_->stats; }
std::uint64_t Engine::ray_passes() const { return impl_->ray_passes; }

}  // namespace caustic
