// SPDX-License-Identifier: LGPL-2.1-or-later
// Shapes a scene file brings for its receivers (a draped cloth, a statue):
// OBJ files with a (u, v) atlas, listed by name in the scene's
// receiver_meshes and read once, with the scene file. A receiver names one
// ("mesh": "cloth") and is placed as a lathe is. A patch may add, move or
// drop receivers of those shapes but never list a file (apply_merge_patch
// refuses the key), so nothing a visitor sends opens one. These meshes are
// scenery, not the object: viewers get them whole to draw the light on.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/receiver_mesh.hpp"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <map>
#include <string>

namespace caustic {

/// At most this many shapes a scene, each of at most this many triangles
/// (a viewer downloads them all; a patch rebuilds a placed one's hierarchy).
inline constexpr std::size_t kMaxReceiverMeshes = 8;
inline constexpr std::size_t kMaxReceiverMeshTriangles = std::size_t{1} << 15;

struct ReceiverMeshTable {
  std::map<std::string, std::string> files;  ///< name -> OBJ path as written, relative to the scene file
  std::map<std::string, Mesh> meshes;        ///< name -> the file's triangles and atlas (Mesh::uvs), its own frame
};

/// Reads `table` (the scene's "receiver_meshes": name -> path) and the files
/// it lists, relative to `base_dir`. Names are 1 to 32 of [a-z0-9_-].
/// Throws SceneError naming "receiver_meshes.<name>"; messages name a file
/// by its base name only.
ReceiverMeshTable load_receiver_meshes(const nlohmann::json& table, const std::filesystem::path& base_dir);

/// The shape in the world: its OBJ's x, y, z along up x normal, up and
/// normal from `center` (a lathe's frame, so both place alike).
ReceiverMesh place_receiver_mesh(const Mesh& shape, const glm::dvec3& center, const glm::dvec3& normal,
                                 const glm::dvec3& up);

/// What a viewer draws a shape from: {"positions": [x, y, z, ...],
/// "uvs": [u, v, ...], "indices": [...]}, in its own frame.
nlohmann::json receiver_mesh_json(const Mesh& shape);

}  // namespace caustic
