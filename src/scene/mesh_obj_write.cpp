// SPDX-License-Identifier: LGPL-2.1-or-later
// OBJ writing of a Mesh, as read_obj() reads it back: a designed face, a
// resampled level or a receiver's shape (with its atlas).
#include "caustic/mesh.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace caustic {

void write_obj(const Mesh& mesh, const std::filesystem::path& file) {
  std::unique_ptr<FILE, int (*)(FILE*)> out(std::fopen(file.string().c_str(), "w"), &std::fclose);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  std::fprintf(out.get(), "# %s, %zu vertices, %zu triangles\n", mesh.uvs.empty() ? "caustic face" : "receiver shape",
               mesh.positions.size(), mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    if (tinted(mesh)) {
      const auto& c = mesh.colours[i];
      std::fprintf(out.get(), "v %.9g %.9g %.9g %.7g %.7g %.7g\n", p.x, p.y, p.z, c.x, c.y, c.z);
    } else {
      std::fprintf(out.get(), "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
    }
  }
  for (const auto& n : mesh.normals) std::fprintf(out.get(), "vn %.7g %.7g %.7g\n", n.x, n.y, n.z);
  for (const auto& uv : mesh.uvs) std::fprintf(out.get(), "vt %.9g %.9g\n", uv.x, uv.y);
  const bool atlas = !mesh.uvs.empty();
  for (const auto& t : mesh.triangles) {
    if (atlas)
      std::fprintf(out.get(), "f %u/%u/%u %u/%u/%u %u/%u/%u\n", t.x + 1, t.x + 1, t.x + 1, t.y + 1, t.y + 1, t.y + 1,
                   t.z + 1, t.z + 1, t.z + 1);
    else
      std::fprintf(out.get(), "f %u//%u %u//%u %u//%u\n", t.x + 1, t.x + 1, t.y + 1, t.y + 1, t.z + 1, t.z + 1);
  }
  // The last buffer is written at the close, so a disk that fills there
  // fails the close alone (a small file: its only write).
  const bool failed = std::ferror(out.get()) != 0;
  if (std::fclose(out.release()) != 0 || failed)
    throw std::runtime_error("error while writing " + file.string() + ": " + std::strerror(errno));
}

}  // namespace caustic
