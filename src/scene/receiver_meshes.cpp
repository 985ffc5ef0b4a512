// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/receiver_meshes.hpp"

#include <nlohmann/json.hpp>

#include <regex>

namespace caustic {

ReceiverMeshTable load_receiver_meshes(const nlohmann::json& table, const std::filesystem::path& base_dir) {
  if (!table.is_object() || table.size() > kMaxReceiverMeshes)
    throw SceneError("receiver_meshes", "must be an object of at most " + std::to_string(kMaxReceiverMeshes) +
                                            " name: \"file.obj\" members");
  static const std::regex name_rule("[a-z0-9_-]{1,32}");
  MeshLimits limits;
  limits.max_triangles = kMaxReceiverMeshTriangles;
  limits.max_vertices = 3 * kMaxReceiverMeshTriangles;
  limits.max_file_bytes = std::uintmax_t{16} << 20;
  ReceiverMeshTable out;
  for (const auto& [name, file] : table.items()) {
    // The name goes into JSON answers and log lines: printable, short, never the key's raw bytes.
    if (!std::regex_match(name, name_rule))
      throw SceneError("receiver_meshes", "names are 1 to 32 of a-z, 0-9, _ and -");
    const std::string key = "receiver_meshes." + name;
    if (!file.is_string() || file.get<std::string>().empty() || file.get<std::string>().size() > 4096)
      throw SceneError(key, "must be the path of an OBJ file, relative to the scene file");
    // As for the scene's mesh: a NUL ends the name where the system reads
    // it ("plate.obj\u0000junk" loaded plate.obj).
    for (unsigned char ch : file.get<std::string>())
      if (ch < 0x20 || ch == 0x7f) throw SceneError(key, "must not hold control characters");
    try {
      out.meshes.emplace(name, load_atlas_obj(base_dir / file.get<std::string>(), limits));
    } catch (const SceneError& e) {
      const std::string what = e.what();  // "mesh: ...": the key this table gives instead
      throw SceneError(key, e.key().empty() ? what : what.substr(e.key().size() + 2));
    }
    out.files.emplace(name, file.get<std::string>());
  }
  return out;
}

ReceiverMesh place_receiver_mesh(const Mesh& shape, const glm::dvec3& center, const glm::dvec3& normal,
                                 const glm::dvec3& up) {
  const glm::dvec3 right = glm::normalize(glm::cross(up, normal));
  std::vector<glm::dvec3> positions;
  positions.reserve(shape.positions.size());
  for (const glm::vec3& p : shape.positions)
    positions.push_back(center + double(p.x) * right + double(p.y) * up + double(p.z) * normal);
  std::vector<glm::dvec2> uvs(shape.uvs.begin(), shape.uvs.end());
  return ReceiverMesh(std::move(positions), std::move(uvs), shape.triangles);
}

nlohmann::json receiver_mesh_json(const Mesh& shape) {
  nlohmann::json positions = nlohmann::json::array(), uvs = nlohmann::json::array(), indices = nlohmann::json::array();
  for (const glm::vec3& p : shape.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
  for (const glm::vec2& t : shape.uvs) uvs.insert(uvs.end(), {t.x, t.y});
  for (const glm::uvec3& t : shape.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});
  return {{"positions", positions}, {"uvs", uvs}, {"indices", indices}};
}

}  // namespace caustic
