#include "frame_source.hpp"

#include "caustic/gst/frame_meta.hpp"

#include <cstring>

namespace caustic::gst {

GstBuffer* produce_frame(FrameSource& source, const ParamStore& params, const MeshLevels& meshes, int width,
                         int height) {
  const bool changed = params.version() != source.rendered;
  if (!changed && !source.readback_pending && source.picture) return gst_buffer_ref(source.picture);
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

  if (changed) {
    ParamStore::Snapshot snap = params.snapshot();
    snap.scene.render.width = width;  // the negotiated caps decide the size
    snap.scene.render.height = height;
    source.rendered = snap.version;
    try {
      source.engine->set_scene(snap.scene, meshes.at(snap.scene.render.mesh_resolution));
      source.last_rejection.clear();
      const std::uint64_t before = source.engine->ray_passes();
      source.engine->render();
      source.renders += source.engine->ray_passes() - before;
      if (source.observer) source.observer(source.engine->stats(), snap.version);
      source.engine->start_ldr_readback(snap.version);
      source.readback_pending = true;
    } catch (const SceneError& e) {
      // Keep showing the last good picture; the store's own checks make this rare.
      source.last_rejection = e.what();
      if (!source.picture) throw;
    }
  }
  Rgba8Image image;
  std::uint64_t version = 0;
  if (source.readback_pending && source.engine->poll_ldr_readback(&image, &version, !source.picture)) {
    source.readback_pending = false;
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, image.pixels.size(), nullptr);
    gst_buffer_fill(buffer, 0, image.pixels.data(), image.pixels.size());
    caustic_buffer_set_frame_meta(buffer, version, 0);
    if (source.picture) gst_buffer_unref(source.picture);
    source.picture = buffer;
    source.version = version;
  }
  return gst_buffer_ref(source.picture);
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
  source.version = source.rendered = 0;
  source.readback_pending = false;
}

}  // namespace caustic::gst
