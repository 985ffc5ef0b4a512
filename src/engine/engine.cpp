#include "caustic/engine.hpp"

#include "passes.hpp"
#include "readback.hpp"

#include <algorithm>
#include <chrono>
#include <optional>

namespace caustic {
namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// Everything but post-processing decides the caustic pass.
bool same_caustic(const Scene& a, const Scene& b) {
  return a.object == b.object && a.light == b.light && a.screen == b.screen && a.render == b.render;
}

}  // namespace


struct Engine::Impl {
  RayPass ray;
  PostPass post;
  gl::RenderTarget hdr, ldr;
  Readback readback;
  std::optional<Scene> scene;
  std::shared_ptr<const Mesh> mesh;
  Placement placement;
  bool ray_dirty = false, post_dirty = false;
  FrameStats stats;
  std::uint64_t ray_passes = 0;
};

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;

void Engine::set_scene(const Scene& scene, std::shared_ptr<const Mesh> mesh) {
  if (!mesh) throw EngineError("set_scene needs a mesh");
  validate_scene(scene);
  Placement placement = place_object(scene.object, *mesh);
  check_geometry(scene, *mesh, placement);

  auto& s = *impl_;
  const bool new_mesh = mesh != s.mesh;
  const bool new_size = !s.scene || s.scene->render.width != scene.render.width ||
                        s.scene->render.height != scene.render.height;
  if (new_mesh) s.ray.upload(*mesh);
  if (new_size) {
    s.hdr = gl::RenderTarget(GL_R32F, scene.render.width, scene.render.height);
    s.ldr = gl::RenderTarget(GL_RGBA8, scene.render.width, scene.render.height);
  }
  s.ray_dirty = s.ray_dirty || new_mesh || new_size || !same_caustic(*s.scene, scene);
  s.post_dirty = s.post_dirty || s.ray_dirty || s.scene->post != scene.post;
  s.scene = scene;
  s.mesh = std::move(mesh);
  s.placement = placement;
}

bool Engine::dirty() const { return impl_->ray_dirty || impl_->post_dirty; }

bool Engine::render() {
  auto& s = *impl_;
  if (!s.scene || !dirty()) return false;
  if (s.ray_dirty) {
    const auto start = std::chrono::steady_clock::now();
    s.ray.draw(*s.scene, s.placement, s.hdr);
    const TriangleCounts counts = s.ray.counts();  // waits for the pass to finish
    glFinish();
    s.stats.ray_ms = elapsed_ms(start);
    s.stats.drawn = counts.drawn;
    s.stats.dropped = counts.dropped;
    s.stats.folded = std::min(counts.positive, counts.negative);
    s.stats.collapsed = counts.collapsed;
    ++s.ray_passes;
  }
  const auto start = std::chrono::steady_clock::now();
  s.post.run(s.scene->post, s.hdr.texture, s.ldr);
  glFinish();
  s.stats.post_ms = elapsed_ms(start);
  if (!s.ray_dirty) s.stats.ray_ms = 0;
  s.ray_dirty = s.post_dirty = false;
  return true;
}

HdrImage Engine::read_hdr() const {
  const auto& t = impl_->hdr.texture;
  HdrImage img{t.width(), t.height(), std::vector<float>(static_cast<std::size_t>(t.width()) * t.height())};
  if (img.pixels.empty()) return img;
  std::vector<float> raw(img.pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(float)), raw.data());
  gl::check_errors("HDR read-back");
  gl::copy_rows_top_first(raw.data(), img.pixels.data(), static_cast<std::size_t>(img.width), img.height);
  return img;
}

Rgba8Image Engine::read_ldr() const {
  const auto& t = impl_->ldr.texture;
  Rgba8Image img{t.width(), t.height(), std::vector<std::uint8_t>(static_cast<std::size_t>(t.width()) * t.height() * 4)};
  if (img.pixels.empty()) return img;
  std::vector<std::uint8_t> raw(img.pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(raw.size()), raw.data());
  gl::check_errors("LDR read-back");
  gl::copy_rows_top_first(raw.data(), img.pixels.data(), static_cast<std::size_t>(img.width) * 4, img.height);
  return img;
}

void Engine::start_ldr_readback(std::uint64_t tag) { impl_->readback.start(impl_->ldr.texture, tag); }

bool Engine::poll_ldr_readback(Rgba8Image* picture, std::uint64_t* tag, bool wait) {
  return impl_->readback.poll(picture, tag, wait);
}

const FrameStats& Engine::stats() const { return impl_->stats; }
std::uint64_t Engine::ray_passes() const { return impl_->ray_passes; }

}  // namespace caustic
