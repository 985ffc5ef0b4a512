#include "frame_source.hpp"

#include "caustic/gst/frame_meta.hpp"

#include <cstring>

namespace caustic::gst {

GstBuffer* produce_frame(FrameSource& source, const ParamStore& params, std::shared_ptr<const Mesh> mesh,
                         int width, int height) {
  if (source.picture && params.version() == source.version) return gst_buffer_ref(source.picture);
  if (!source.context) {
    source.context = std::make_unique<GlContext>(egl_platform_from_environment());
    source.engine = std::make_unique<Engine>();
  }
  // The context is current only while drawing, so that stopping the element
  // on another thread can free it.
  source.context->make_current();
  struct Release {
    GlContext* c;
    ~Release() { c->release_current(); }
  } release_guard{source.context.get()};

  ParamStore::Snapshot snap = params.snapshot();
  snap.scene.render.width = width;  // the negotiated caps decide the size
  snap.scene.render.height = height;
  try {
    source.engine->set_scene(snap.scene, std::move(mesh));
    source.last_rejection.clear();
  } catch (const SceneError& e) {
    // Keep showing the last good picture; the store's own checks make this rare.
    source.last_rejection = e.what();
    if (source.picture) {
      source.version = snap.version;
      return gst_buffer_ref(source.picture);
    }
    throw;
  }
  const std::uint64_t before = source.engine->ray_passes();
  source.engine->render();
  source.renders += source.engine->ray_passes() - before;
  if (source.observer) source.observer(source.engine->stats(), snap.version);
  const Rgba8Image image = source.engine->read_ldr();

  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, image.pixels.size(), nullptr);
  gst_buffer_fill(buffer, 0, image.pixels.data(), image.pixels.size());
  caustic_buffer_set_frame_meta(buffer, snap.version, 0);
  if (source.picture) gst_buffer_unref(source.picture);
  source.picture = buffer;
  source.version = snap.version;
  return gst_buffer_ref(buffer);
}

void release(FrameSource& source) {
  if (source.picture) gst_buffer_unref(source.picture);
  source.picture = nullptr;
  if (source.context) {
    source.context->make_current();
    source.engine.reset();
    source.context->release_current();
    source.context.reset();
  }
  source.version = 0;
}

}  // namespace caustic::gst
