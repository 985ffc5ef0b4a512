// SPDX-License-Identifier: LGPL-2.1-or-later
#include "design_files.hpp"

#include "caustic/json_text.hpp"

namespace caustic::server {

std::string read_text(const std::filesystem::path& file, std::size_t limit) {
  FileText read = read_file_text(file, limit);
  return read.opened && !read.too_large ? std::move(read.text) : std::string();
}

nlohmann::json public_report(const nlohmann::json& r) {
  nlohmann::json out = {{"resolution", r.value("resolution", 0)},
                        {"design_seconds", r.value("design_seconds", 0.0)},
                        {"seconds_total", r.value("seconds_total", 0.0)},
                        {"tir_vertices", r.value("tir_vertices", 0)},
                        // The share of the light the solve left misplaced: how far
                        // the glass can be trusted, a figure of the method, not of the mesh.
                        {"transport_residual", r.value("transport_residual", 0.0)}};
  if (r.contains("engine") && r["engine"].is_object())
    out["engine"] = {{"ssim", r["engine"].value("ssim", 0.0)},
                     {"relative_l1", r["engine"].value("relative_l1", 0.0)},
                     {"leak", r["engine"].value("leak", 0.0)}};
  // A colour design: how close each channel and the hues come to the picture.
  if (r.contains("engine") && r["engine"].is_object() && r["engine"].contains("colour") &&
      r["engine"]["colour"].is_object()) {
    const auto& c = r["engine"]["colour"];
    out["engine"]["chromaticity_error"] = c.value("chromaticity_error", 0.0);
    out["engine"]["relative_l1_rgb"] = c.value("relative_l1_rgb", nlohmann::json::array());
  }
  // What the upload held that was not designed, said in the designer's
  // words (no path); a file edited by hand gives only well-formed entries.
  out["warnings"] = nlohmann::json::array();
  if (const auto w = r.find("warnings"); w != r.end() && w->is_array())
    for (const auto& one : *w)
      if (one.is_object() && one.contains("key") && one["key"].is_string() && one.contains("detail") &&
          one["detail"].is_string() && out["warnings"].size() < 8)
        out["warnings"].push_back({{"key", one["key"]}, {"detail", one["detail"]}});
  return out;
}

}  // namespace caustic::server
