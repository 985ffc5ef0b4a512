// SPDX-License-Identifier: LGPL-2.1-or-later
// CausticFrameMeta: which parameter version (and which fidelity level) a
// buffer's picture shows, so every later stage can tell which change a frame
// reflects.
#pragma once

#include <gst/gst.h>

#include <cstdint>

struct CausticFrameMeta {
  GstMeta meta;
  std::uint64_t version;  ///< ParamStore version the picture was rendered from
  std::uint32_t level;    ///< fidelity level; 0 is full quality
};

GType caustic_frame_meta_api_get_type();
const GstMetaInfo* caustic_frame_meta_get_info();

/// Attaches (or overwrites) the meta on a writable buffer.
CausticFrameMeta* caustic_buffer_set_frame_meta(GstBuffer* buffer, std::uint64_t version, std::uint32_t level);

/// The meta on `buffer`, or nullptr.
inline CausticFrameMeta* caustic_buffer_get_frame_meta(GstBuffer* buffer) {
  return reinterpret_cast<CausticFrameMeta*>(gst_buffer_get_meta(buffer, caustic_frame_meta_api_get_type()));
}
