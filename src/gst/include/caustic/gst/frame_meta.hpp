// SPDX-License-Identifier: LGPL-2.1-or-later
// CausticFrameMeta: which parameter version (and which fidelity level) a
// buffer's picture shows, so every later stage can tell which change a frame
// reflects; of a scene with water, also which step of the water.
#pragma once

#include <gst/gst.h>

#include <cstdint>

struct CausticFrameMeta {
  GstMeta meta;
  std::uint64_t version;  ///< ParamStore version the picture was rendered from
  std::uint32_t level;    ///< fidelity level; 0 is full quality
  std::uint64_t water_step;  ///< the water solver's step the surface shows (0: no water, or still)
};

GType caustic_frame_meta_api_get_type();
const GstMetaInfo* caustic_frame_meta_get_info();

/// Attaches (or overwrites) the meta on a writable buffer.
CausticFrameMeta* caustic_buffer_set_frame_meta(GstBuffer* buffer, std::uint64_t version, std::uint32_t level,
                                                std::uint64_t water_step = 0);

/// The meta on `buffer`, or nullptr.
inline CausticFrameMeta* caustic_buffer_get_frame_meta(GstBuffer* buffer) {
  return reinterpret_cast<CausticFrameMeta*>(gst_buffer_get_meta(buffer, caustic_frame_meta_api_get_type()));
}
