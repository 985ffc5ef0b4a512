// SPDX-License-Identifier: LGPL-2.1-or-later
// A curved receiver's world-space triangles and search tree, shared by the
// scenes that ask for the same one. A parameter patch reads its whole scene
// again (twice: once to check the fixed keys, once to apply it), and every
// lathe and shape was built anew each time: seven lathes held the server's
// main loop 0.3 s a patch. Every one a scene holds is found, and the last
// few that no scene holds are kept; a shape is known by its table (held
// weakly, so that a table read later at the same address is never taken
// for it), its name and where it stands.
#pragma once

#include "caustic/receiver_mesh.hpp"
#include "caustic/receiver_meshes.hpp"

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace caustic {

/// make_lathe(profile, segments, base, normal, up), or the one made last time.
std::shared_ptr<const ReceiverMesh> lathe_mesh(const std::vector<glm::dvec2>& profile, int segments,
                                               const glm::dvec3& base, const glm::dvec3& normal, const glm::dvec3& up);

/// place_receiver_mesh(table->meshes.at(name), center, normal, up), or the
/// one made last time; `table` must hold `name`.
std::shared_ptr<const ReceiverMesh> shape_mesh(const std::shared_ptr<const ReceiverMeshTable>& table,
                                               const std::string& name, const glm::dvec3& center,
                                               const glm::dvec3& normal, const glm::dvec3& up);

}  // namespace caustic
