// SPDX-License-Identifier: LGPL-2.1-or-later
// causticsrc's properties: their specs, and their reads and writes under
// the settings lock. Apart from the element's streaming so that each half
// reads on its own.
#include "causticsrc_state.hpp"

#include <chrono>
#include <string>

GST_DEBUG_CATEGORY_EXTERN(caustic_src_debug);
#define GST_CAT_DEFAULT caustic_src_debug

namespace caustic::gst {
namespace {

enum { PROP_0, PROP_SCENE, PROP_WIDTH, PROP_HEIGHT, PROP_FRAMERATE, PROP_RENDERS, PROP_OVERRUNS, PROP_PROGRESSIVE, PROP_SETTLE_MS,
       PROP_PREVIEW_DIVISOR, PROP_PREVIEW_MESH, PROP_PICTURE_VERSION,
       PROP_STILL_INTERVAL_MS, PROP_SKIPPED, PROP_WATER_SOLVER, PROP_EARLY_FRAMES };

State& state_of(gpointer self) { return *reinterpret_cast<GstCausticSrc*>(self)->state; }

}  // namespace

void set_property(GObject* object, guint id, const GValue* value, GParamSpec* pspec) {
  State& s = state_of(object);
  // Every writable property is GST_PARAM_MUTABLE_READY: the streaming and
  // render threads read them without a lock. A write while streaming is
  // refused, the value kept, rather than raced.
  GST_OBJECT_LOCK(object);
  const GstState state = GST_STATE(object);
  GST_OBJECT_UNLOCK(object);
  if (state > GST_STATE_READY) {
    GST_WARNING_OBJECT(object, "property %s is changeable only in the NULL or READY state: kept as it was",
                       g_param_spec_get_name(pspec));
    return;
  }
  std::lock_guard lock(s.lock);
  switch (id) {
    case PROP_SCENE: {
      std::string path = g_value_get_string(value) ? g_value_get_string(value) : "";
      // A scene loaded from the old file is dropped: the next start loads the new one.
      if (path != s.scene_path && s.from_file) s.params.reset(), s.meshes.reset(), s.pool.reset(), s.from_file = false;
      s.scene_path = std::move(path);
      break;
    }
    case PROP_WIDTH: s.width = g_value_get_int(value); break;
    case PROP_HEIGHT: s.height = g_value_get_int(value); break;
    case PROP_FRAMERATE:
      s.fps_n = gst_value_get_fraction_numerator(value);
      s.fps_d = gst_value_get_fraction_denominator(value);
      break;
    case PROP_PROGRESSIVE: s.source.progressive.enabled = g_value_get_boolean(value); break;
    case PROP_SETTLE_MS: s.source.progressive.settle = std::chrono::milliseconds(g_value_get_uint(value)); break;
    case PROP_PREVIEW_DIVISOR: s.source.progressive.divisor = g_value_get_int(value); break;
    case PROP_PREVIEW_MESH: s.source.progressive.mesh = g_value_get_int(value); break;
    case PROP_STILL_INTERVAL_MS: s.still_interval = g_value_get_uint(value) * GST_MSECOND; break;
    case PROP_WATER_SOLVER: s.source.water_solver = static_cast<WaterSolver>(g_value_get_enum(value)); break;
    case PROP_EARLY_FRAMES: s.early_frames = g_value_get_boolean(value) != FALSE; break;
    default: G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

void get_property(GObject* object, guint id, GValue* value, GParamSpec* pspec) {
  State& s = state_of(object);
  std::lock_guard lock(s.lock);
  switch (id) {
    case PROP_SCENE: g_value_set_string(value, s.scene_path.c_str()); break;
    case PROP_WIDTH: g_value_set_int(value, s.width); break;
    case PROP_HEIGHT: g_value_set_int(value, s.height); break;
    case PROP_FRAMERATE: gst_value_set_fraction(value, s.fps_n, s.fps_d); break;
    case PROP_RENDERS: g_value_set_uint64(value, s.source.renders.load()); break;
    case PROP_OVERRUNS: g_value_set_uint64(value, s.overruns.load()); break;
    case PROP_PICTURE_VERSION: g_value_set_uint64(value, s.source.picture_version.load()); break;
    case PROP_PROGRESSIVE: g_value_set_boolean(value, s.source.progressive.enabled); break;
    case PROP_SETTLE_MS: g_value_set_uint(value, static_cast<guint>(s.source.progressive.settle.count())); break;
    case PROP_PREVIEW_DIVISOR: g_value_set_int(value, s.source.progressive.divisor); break;
    case PROP_PREVIEW_MESH: g_value_set_int(value, s.source.progressive.mesh); break;
    case PROP_STILL_INTERVAL_MS: g_value_set_uint(value, static_cast<guint>(s.still_interval / GST_MSECOND)); break;
    case PROP_SKIPPED: g_value_set_uint64(value, s.skipped.load()); break;
    case PROP_WATER_SOLVER: g_value_set_enum(value, static_cast<gint>(s.source.water_solver)); break;
    case PROP_EARLY_FRAMES: g_value_set_boolean(value, s.early_frames.load()); break;
    default: G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

void install_properties(GObjectClass* gobject) {
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS | GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(gobject, PROP_SCENE,
                                  g_param_spec_string("scene", "Scene", "Scene file (JSON) to render", "", rw));
  g_object_class_install_property(
      gobject, PROP_WIDTH, g_param_spec_int("width", "Width", "Width in pixels; 0: the scene's", 0, 8192, 0, rw));
  g_object_class_install_property(
      gobject, PROP_HEIGHT, g_param_spec_int("height", "Height", "Height in pixels; 0: the scene's", 0, 8192, 0, rw));
  g_object_class_install_property(gobject, PROP_FRAMERATE,
                                  gst_param_spec_fraction("framerate", "Frame rate", "Frames per second", 1, 1, 240,
                                                          1, 30, 1, rw));
  g_object_class_install_property(
      gobject, PROP_RENDERS,
      g_param_spec_uint64("renders", "Renders", "Caustic passes drawn so far (unchanged frames are re-sent)", 0,
                          G_MAXUINT64, 0, static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject, PROP_OVERRUNS,
      g_param_spec_uint64("overruns", "Overruns",
                          "Frames sent while a render outlasted its frame interval (the previous picture went out again)",
                          0, G_MAXUINT64, 0, static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject, PROP_PICTURE_VERSION,
      g_param_spec_uint64("picture-version", "Picture version",
                          "Parameters version of the newest finished picture (the next frame due takes it)", 0,
                          G_MAXUINT64, 0, static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject, PROP_PROGRESSIVE,
      g_param_spec_boolean("progressive", "Progressive", "Cheap previews while the parameters change, then one full frame",
                           TRUE, rw));
  g_object_class_install_property(
      gobject, PROP_SETTLE_MS,
      g_param_spec_uint("settle-ms", "Settle time", "Stillness (ms) after which the full-quality frame is drawn", 0,
                        10000, 40, rw));
  g_object_class_install_property(
      gobject, PROP_PREVIEW_DIVISOR,
      g_param_spec_int("preview-divisor", "Preview divisor", "Previews draw the caustic at 1/N of the size per side",
                       1, 16, 2, rw));
  g_object_class_install_property(
      gobject, PROP_PREVIEW_MESH,
      g_param_spec_int("preview-mesh", "Preview mesh", "Mesh level of previews (vertices per side) when coarser", 2,
                       2048, 32, rw));
  g_object_class_install_property(
      gobject, PROP_STILL_INTERVAL_MS,
      g_param_spec_uint("still-interval-ms", "Still interval",
                        "While the picture is unchanged, send it again only this often (ms; a key frame request "
                        "sends the next frame at once); 0: every frame at the frame rate",
                        0, 60000, 0, rw));
  g_object_class_install_property(
      gobject, PROP_SKIPPED,
      g_param_spec_uint64("skipped", "Skipped", "Frames not sent because the picture was unchanged (still-interval-ms)",
                          0, G_MAXUINT64, 0, static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject, PROP_WATER_SOLVER,
      g_param_spec_enum("water-solver", "Water solver", "Where a scene's water steps: auto, cpu or gl",
                        water_solver_type(), 0, rw));
  g_object_class_install_property(
      gobject, PROP_EARLY_FRAMES,
      g_param_spec_boolean("early-frames", "Early frames",
                           "A picture finished while the stream stands still (still-interval-ms) leaves at once, "
                           "not at the next frame time, once an interval has passed since the last frame",
                           TRUE, rw));
}

}  // namespace caustic::gst
