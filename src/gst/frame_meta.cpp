// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/gst/frame_meta.hpp"

GType caustic_frame_meta_api_get_type() {
  static GType type = 0;
  static const gchar* tags[] = {nullptr};  // survives any transformation: it describes content, not layout
  if (g_once_init_enter(&type)) {
    GType t = gst_meta_api_type_register("CausticFrameMetaAPI", tags);
    g_once_init_leave(&type, t);
  }
  return type;
}

namespace {

gboolean meta_init(GstMeta* meta, gpointer, GstBuffer*) {
  auto* m = reinterpret_cast<CausticFrameMeta*>(meta);
  m->version = 0;
  m->level = 0;
  m->water_step = 0;
  return TRUE;
}

gboolean meta_transform(GstBuffer* dest, GstMeta* meta, GstBuffer*, GQuark, gpointer) {
  const auto* m = reinterpret_cast<CausticFrameMeta*>(meta);
  return caustic_buffer_set_frame_meta(dest, m->version, m->level, m->water_step) != nullptr;
}

}  // namespace

const GstMetaInfo* caustic_frame_meta_get_info() {
  static const GstMetaInfo* info = nullptr;
  if (g_once_init_enter(&info)) {
    const GstMetaInfo* i = gst_meta_register(caustic_frame_meta_api_get_type(), "CausticFrameMeta",
                                             sizeof(CausticFrameMeta), meta_init, nullptr, meta_transform);
    g_once_init_leave(&info, i);
  }
  return info;
}

CausticFrameMeta* caustic_buffer_set_frame_meta(GstBuffer* buffer, std::uint64_t version, std::uint32_t level,
                                                std::uint64_t water_step) {
  auto* m = caustic_buffer_get_frame_meta(buffer);
  if (!m)
    m = reinterpret_cast<CausticFrameMeta*>(gst_buffer_add_meta(buffer, caustic_frame_meta_get_info(), nullptr));
  if (m) {
    m->version = version;
    m->level = level;
    m->water_step = water_step;
  }
  return m;
}
