// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * SECTION:element-causticsrc
 * @title: causticsrc
 *
 * A live source of caustics: the light pattern that a refractive or
 * reflective object throws on a screen, rendered with OpenGL in a headless
 * EGL context of its own (a GPU when there is one, llvmpipe otherwise). It
 * renders again only when the parameters changed and otherwise re-sends the
 * last picture, at the frame rate or, with still-interval-ms, only that
 * often. A force-key-unit event that reaches it sends the next frame at
 * once, so that an encoder can answer it (encoders keep a viewer's request
 * to themselves: causticd passes it on to the element too), and with
 * early-frames a change after a still spell leaves as soon as it is drawn.
 * Every buffer carries a CausticFrameMeta with the parameter version it
 * shows and its fidelity level. Properties change in the NULL or READY
 * state only; a new scene file is loaded at the next start. While the parameters keep
 * changing (progressive=true), frames are previews (level 1: a coarser mesh
 * level, the caustic at 1/preview-divisor of the size, no bloom); once they
 * have been still for settle-ms, one full-quality frame (level 0) follows
 * (a spectral one, left standing 0.5 s, again at render.still_wavelengths).
 * Water moves by the stream's clock, stepped on the GL when the renderer is
 * a GPU (water-solver=auto), or where water-solver says.
 *
 * ## Example launch line
 * |[
 * gst-launch-1.0 causticsrc scene=/usr/share/causticd/assets/scenes/lens.json framerate=30/1 ! videoconvert ! autovideosink
 * ]|
 * It produces RGBA or I420; I420 is converted on the GPU (BT.601, limited
 * range) and read back at 1.5 bytes a pixel, so an encoder needs no
 * videoconvert in front of it:
 * |[
 * gst-launch-1.0 causticsrc scene=/usr/share/causticd/assets/scenes/lens.json width=1024 height=1024 ! video/x-raw,format=I420 ! vp8enc deadline=1 ! fakesink
 * ]|
 * Outside causticd the element comes from the plugin file libgstcaustic.so
 * (installed in GStreamer's plugin folder, or found through GST_PLUGIN_PATH);
 * this launch line writes two seconds of VP8:
 * |[
 * gst-launch-1.0 causticsrc scene=/usr/share/causticd/assets/scenes/lens.json width=512 height=512 num-buffers=60 ! video/x-raw,format=I420 ! vp8enc deadline=1 ! webmmux ! filesink location=out.webm
 * ]|
 * causticd registers the same element as a static plugin of its own.
 */
#include "caustic/gst/causticsrc.hpp"

#include "caustic/gst/frame_meta.hpp"
#include "caustic/height_field.hpp"
#include "causticsrc_state.hpp"

using caustic::gst::State;

GST_DEBUG_CATEGORY(caustic_src_debug);  // frame_source.cpp logs into it too
#define GST_CAT_DEFAULT caustic_src_debug

G_DEFINE_TYPE(GstCausticSrc, gst_caustic_src, GST_TYPE_PUSH_SRC)

static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("video/x-raw, format=(string){ RGBA, I420 }, width=(int)[16, 8192], height=(int)[16, 8192], "
                    "framerate=(fraction)[1/1, 240/1]"));

static State& state_of(gpointer self) { return *reinterpret_cast<GstCausticSrc*>(self)->state; }

static GstCaps* gst_caustic_src_fixate(GstBaseSrc* src, GstCaps* caps) {
  State& s = state_of(src);
  int width, height, fps_n, fps_d;
  {
    std::lock_guard lock(s.lock);
    const auto scene = s.params ? std::optional(s.params->snapshot().scene) : std::nullopt;
    width = s.width ? s.width : (scene ? scene->render.width : 1024);
    height = s.height ? s.height : (scene ? scene->render.height : 1024);
    fps_n = s.fps_n;
    fps_d = s.fps_d;
  }
  caps = gst_caps_make_writable(caps);
  GstStructure* st = gst_caps_get_structure(caps, 0);
  gst_structure_fixate_field_nearest_int(st, "width", width);
  gst_structure_fixate_field_nearest_int(st, "height", height);
  gst_structure_fixate_field_nearest_fraction(st, "framerate", fps_n, fps_d);
  return GST_BASE_SRC_CLASS(gst_caustic_src_parent_class)->fixate(src, caps);
}

static gboolean gst_caustic_src_set_caps(GstBaseSrc* src, GstCaps* caps) {
  State& s = state_of(src);
  GstVideoInfo info;
  if (!gst_video_info_from_caps(&info, caps) || GST_VIDEO_INFO_FPS_N(&info) <= 0) return FALSE;
  if (GST_VIDEO_INFO_FORMAT(&info) == GST_VIDEO_FORMAT_I420) {
    // The GPU writes the planes packed; GStreamer's layout must be that one.
    const int w = GST_VIDEO_INFO_WIDTH(&info), h = GST_VIDEO_INFO_HEIGHT(&info);
    if (w % 8 || h % 2) {
      GST_ELEMENT_ERROR(src, CORE, NEGOTIATION, ("I420 needs a width divisible by 8 and an even height"),
                        ("got %dx%d", w, h));
      return FALSE;
    }
  }
  caustic::gst::renegotiate(s, info);  // the worker goes first when it drew for other caps
  s.source.format =
      GST_VIDEO_INFO_FORMAT(&info) == GST_VIDEO_FORMAT_I420 ? caustic::PixelFormat::i420 : caustic::PixelFormat::rgba;
  gst_base_src_set_blocksize(src, static_cast<guint>(GST_VIDEO_INFO_SIZE(&s.info)));
  s.frame_duration = gst_util_uint64_scale(GST_SECOND, GST_VIDEO_INFO_FPS_D(&s.info), GST_VIDEO_INFO_FPS_N(&s.info));
  s.source.frame_interval = std::chrono::nanoseconds(s.frame_duration.load());
  return TRUE;
}

static gboolean gst_caustic_src_start(GstBaseSrc* src) {
  State& s = state_of(src);
  std::lock_guard lock(s.lock);
  s.frame_index = s.first_index = 0;
  s.first_due = 0;
  if (s.params && s.meshes) {
    start_water(s);
    return TRUE;
  }
  if (s.scene_path.empty()) {
    GST_ELEMENT_ERROR(src, RESOURCE, NOT_FOUND, ("No scene"), ("set the scene property or call set_source"));
    return FALSE;
  }
  try {
    const caustic::Scene scene = caustic::load_scene(s.scene_path);
    s.pool.reset();  // another file's water, from a start that failed after making it, is not this scene's
    auto meshes = std::make_shared<caustic::MeshLevels>();
    // Water is warmed up once: its pool's first surface is the mesh.
    if (scene.water) s.pool = std::make_shared<caustic::water::Pool>(*scene.water);
    meshes->source = s.pool ? s.pool->mesh() : std::make_shared<const caustic::Mesh>(caustic::load_face(scene));
    // Only the mesh as loaded here: a scene naming a coarser level is refused.
    s.params = std::make_shared<caustic::ParamStore>(
        scene, [meshes](const caustic::Scene& candidate) { caustic::check_geometry(candidate, *meshes); });
    s.meshes = std::move(meshes);
    s.from_file = true;
    start_water(s);
  } catch (const std::exception& e) {
    GST_ELEMENT_ERROR(src, RESOURCE, READ, ("Cannot load scene %s", s.scene_path.c_str()), ("%s", e.what()));
    return FALSE;
  }
  return TRUE;
}

static void forget_last_sent(State& s) {
  if (s.last_sent) gst_buffer_unref(s.last_sent);
  s.last_sent = nullptr;
}

static gboolean gst_caustic_src_stop(GstBaseSrc* src) {
  State& s = state_of(src);
  forget_last_sent(s);
  s.worker.reset();  // joins the render thread, which frees its GL context
  caustic::gst::release(s.source);
  caustic::gst::answer_snapshots(s.source);  // requests that came too late get no picture
  return TRUE;
}

// Live: each buffer's running time is when it is due; GstBaseSrc waits for it.
static void gst_caustic_src_get_times(GstBaseSrc*, GstBuffer* buffer, GstClockTime* start, GstClockTime* end) {
  *start = GST_BUFFER_PTS(buffer);
  *end = GST_CLOCK_TIME_IS_VALID(*start) && GST_BUFFER_DURATION_IS_VALID(buffer)
             ? *start + GST_BUFFER_DURATION(buffer)
             : GST_CLOCK_TIME_NONE;
}

static gboolean gst_caustic_src_query(GstBaseSrc* src, GstQuery* query) {
  State& s = state_of(src);
  // Any thread asks, while the streaming thread may be setting new caps:
  // the interval is read from its own atomic, not from s.info.
  if (const GstClockTime frame = s.frame_duration; GST_QUERY_TYPE(query) == GST_QUERY_LATENCY && frame > 0) {
    // A frame leaves when due, with a picture finished before that: within
    // one frame interval unless a render overran.
    gst_query_set_latency(query, TRUE, frame, frame);
    return TRUE;
  }
  return GST_BASE_SRC_CLASS(gst_caustic_src_parent_class)->query(src, query);
}

// A key frame asked for from downstream: the encoder makes it, but only
// from a frame it is given, so the next frame goes out even if unchanged.
static gboolean gst_caustic_src_event(GstBaseSrc* src, GstEvent* event) {
  if (gst_video_event_is_force_key_unit(event)) {
    state_of(src).send_next = true;
    return TRUE;
  }
  return GST_BASE_SRC_CLASS(gst_caustic_src_parent_class)->event(src, event);
}

static gboolean gst_caustic_src_unlock(GstBaseSrc* src) {
  state_of(src).flushing = true;  // also ends a wait for the first picture
  state_of(src).due_wait.unlock();
  return TRUE;
}

static gboolean gst_caustic_src_unlock_stop(GstBaseSrc* src) {
  state_of(src).flushing = false;
  state_of(src).due_wait.unlock_stop();
  return TRUE;
}

static GstFlowReturn gst_caustic_src_create(GstPushSrc* push, GstBuffer** out) {
  State& s = state_of(push);
  std::shared_ptr<caustic::ParamStore> params;
  std::shared_ptr<const caustic::MeshLevels> meshes;
  {
    std::lock_guard lock(s.lock);
    params = s.params;
    meshes = s.meshes;
  }
  const gint n = GST_VIDEO_INFO_FPS_N(&s.info), d = GST_VIDEO_INFO_FPS_D(&s.info);
  const int width = GST_VIDEO_INFO_WIDTH(&s.info), height = GST_VIDEO_INFO_HEIGHT(&s.info);
  GstClockTime due = 0;
  GstBuffer* picture = nullptr;
  try {
    if (!s.worker || s.worker->width() != width || s.worker->height() != height) {
      s.worker.reset();
      s.worker = std::make_unique<caustic::gst::FrameWorker>(s.source, params, meshes, width, height, &s.heartbeat,
                                                             [&s] { s.due_wait.interrupt(); }, &s.flushing);
      s.overruns_told = 0;  // the new worker counts its own
    }
    if (const GstFlowReturn r = caustic::gst::next_frame(s, GST_ELEMENT(push), &picture, &due); r != GST_FLOW_OK)
      return r;
    const CausticFrameMeta* meta = caustic_buffer_get_frame_meta(picture);
    const std::uint64_t renders = s.source.renders;
    if (renders != s.renders_logged)
      GST_DEBUG_OBJECT(push, "frame %" G_GUINT64_FORMAT ": %" G_GUINT64_FORMAT " new render(s), showing version %"
                       G_GUINT64_FORMAT " level %u", s.frame_index, renders - s.renders_logged, meta->version,
                       meta->level);
    else
      GST_LOG_OBJECT(push, "frame %" G_GUINT64_FORMAT ": re-sent version %" G_GUINT64_FORMAT, s.frame_index,
                     meta->version);
    s.renders_logged = renders;
    for (; s.overruns_told < s.worker->overruns(); ++s.overruns_told) {
      GST_DEBUG_OBJECT(push, "frame %" G_GUINT64_FORMAT ": render overran the frame interval; previous picture re-sent",
                       s.frame_index);
      ++s.overruns;
      if (s.on_overrun) s.on_overrun();
    }
  } catch (const std::exception& e) {
    GST_ELEMENT_ERROR(push, LIBRARY, FAILED, ("Cannot render the caustic"), ("%s", e.what()));
    return GST_FLOW_ERROR;
  }
  // A shallow copy shares the pixels; timestamps are this frame's own.
  GstBuffer* buffer = gst_buffer_copy(picture);
  gst_buffer_unref(picture);
  GST_BUFFER_PTS(buffer) = due;
  GST_BUFFER_DURATION(buffer) = gst_util_uint64_scale((s.frame_index + 1) * GST_SECOND, d, n) -
                                gst_util_uint64_scale(s.frame_index * GST_SECOND, d, n);
  GST_BUFFER_OFFSET(buffer) = s.frame_index;
  GST_BUFFER_OFFSET_END(buffer) = ++s.frame_index;
  *out = buffer;
  return GST_FLOW_OK;
}

static void gst_caustic_src_finalize(GObject* object) {
  auto* self = reinterpret_cast<GstCausticSrc*>(object);
  forget_last_sent(*self->state);
  self->state->worker.reset();
  caustic::gst::release(self->state->source);
  caustic::gst::answer_snapshots(self->state->source);  // with none: the element goes without streaming again
  delete self->state;
  G_OBJECT_CLASS(gst_caustic_src_parent_class)->finalize(object);
}

static void gst_caustic_src_class_init(GstCausticSrcClass* klass) {
  auto* gobject = G_OBJECT_CLASS(klass);
  auto* element = GST_ELEMENT_CLASS(klass);
  auto* basesrc = GST_BASE_SRC_CLASS(klass);
  gobject->set_property = caustic::gst::set_property;
  gobject->get_property = caustic::gst::get_property;
  gobject->finalize = gst_caustic_src_finalize;
  caustic::gst::install_properties(gobject);
  gst_element_class_set_static_metadata(element, "Caustic source", "Source/Video",
                                        "Renders the caustic of a refractive or reflective object, live",
                                        "causticd developers");
  gst_element_class_add_static_pad_template(element, &src_template);
  basesrc->fixate = gst_caustic_src_fixate;
  basesrc->set_caps = gst_caustic_src_set_caps;
  basesrc->start = gst_caustic_src_start;
  basesrc->stop = gst_caustic_src_stop;
  basesrc->get_times = gst_caustic_src_get_times;
  basesrc->query = gst_caustic_src_query;
  basesrc->event = gst_caustic_src_event;
  basesrc->unlock = gst_caustic_src_unlock;
  basesrc->unlock_stop = gst_caustic_src_unlock_stop;
  GST_PUSH_SRC_CLASS(klass)->create = gst_caustic_src_create;
  GST_DEBUG_CATEGORY_INIT(caustic_src_debug, "causticsrc", 0, "caustic source");
}

static void gst_caustic_src_init(GstCausticSrc* self) {
  self->state = new State();
  gst_video_info_init(&self->state->info);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
}

namespace caustic::gst {

bool register_element(GstPlugin* plugin) {
  return gst_element_register(plugin, "causticsrc", GST_RANK_NONE, gst_caustic_src_get_type());
}

bool register_elements() {
  static const bool ok = gst_plugin_register_static(
      GST_VERSION_MAJOR, GST_VERSION_MINOR, "caustic", "Caustic rendering",
      [](GstPlugin* plugin) -> gboolean { return register_element(plugin); }, CAUSTICD_VERSION, "LGPL", "causticd",
      "causticd", "https://localhost.localdomain/causticd");
  return ok;
}

}  // namespace caustic::gst
