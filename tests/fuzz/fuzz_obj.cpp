// SPDX-License-Identifier: LGPL-2.1-or-later
// load_obj reads the caustic face through tinyobjloader (compiled into this
// target, so it is instrumented too). Small limits keep a hostile file from
// passing for a memory problem of the fuzzer's own.
#include "caustic/mesh.hpp"
#include "fuzz_support.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // load_obj refuses "mtllib" before tinyobjloader could open another file
  // (here it would be one of the fuzzer's own /proc/self/fd entries).
  caustic::MeshLimits limits;
  limits.max_vertices = 2048;
  limits.max_triangles = 4096;
  limits.max_file_bytes = 64 * 1024;
  caustic::fuzz::MemFile file(data, size);
  caustic::Mesh mesh;
  try {
    mesh = caustic::load_obj(file.path(), limits);
  } catch (const caustic::SceneError& e) {
    FUZZ_CHECK(std::strlen(e.what()) > 0);
    return 0;
  }
  FUZZ_CHECK(!mesh.triangles.empty());
  FUZZ_CHECK(mesh.positions.size() <= limits.max_vertices);
  FUZZ_CHECK(mesh.triangles.size() <= limits.max_triangles);
  FUZZ_CHECK(mesh.normals.size() == mesh.positions.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) FUZZ_CHECK(t[k] < mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      FUZZ_CHECK(std::isfinite(mesh.positions[i][k]));
      FUZZ_CHECK(std::abs(mesh.positions[i][k]) <= limits.max_coordinate);
    }
    FUZZ_CHECK(std::abs(glm::length(mesh.normals[i]) - 1.0f) <= 1e-3f);
  }
  return 0;
}
