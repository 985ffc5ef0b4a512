// SPDX-License-Identifier: LGPL-2.1-or-later
// The caustic face of an object: an indexed triangle mesh with one normal per
// vertex, and where it sits in the world.
#pragma once

#include "caustic/scene.hpp"

#include <glm/glm.hpp>

#include <array>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace caustic {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  ///< unit, one per position; orientation is free
  std::vector<glm::uvec3> triangles;
  /// Optional tint (report 3.6): one linear-RGB transmittance in [0, 1] per
  /// position, from OBJ vertex colours. Light crossing the face near a
  /// vertex keeps that fraction of its flux per channel; a triangle passes
  /// the mean of its corners (the exact mean of the linear interpolation).
  /// Empty: clear glass, and a grey frame unless the glass disperses.
  std::vector<glm::vec3> colours;
  /// A receiver's atlas (load_atlas_obj): one (u, v) in [0, 1]^2 per
  /// position, from the file's `vt`. Empty on a caustic face.
  std::vector<glm::vec2> uvs;
};

/// Whether the face filters light by colour, so frames of it are RGB.
inline bool tinted(const Mesh& mesh) { return !mesh.colours.empty(); }

/// Bounds that load_obj enforces, so a hostile file cannot exhaust memory.
struct MeshLimits {
  std::size_t max_vertices = std::size_t{1} << 22;
  std::size_t max_triangles = std::size_t{1} << 23;
  std::uintmax_t max_file_bytes = std::uintmax_t{1} << 30;
  double max_coordinate = 1e6;
};

/// Loads an OBJ holding the caustic face as triangles. Positions with
/// different normals become separate vertices; a file with no normals (or
/// some faces without) gets area-weighted smooth normals. Vertex colours
/// (`v x y z r g b`, each in [0, 1]) become Mesh::colours; every vertex
/// has one or none does. Throws SceneError
/// with a message that names the problem (and the line for syntax errors).
Mesh load_obj(const std::filesystem::path& file, const MeshLimits& limits = {});

/// Loads an OBJ whose faces carry an atlas (`f v/vt/vn` or `f v/vt`): a
/// receiver's shape (caustic/receiver_meshes.hpp). As load_obj, and every
/// face corner must name a `vt` in [0, 1]^2; corners that share a position
/// but not a `vt` (a seam of the atlas) become separate vertices.
Mesh load_atlas_obj(const std::filesystem::path& file, const MeshLimits& limits = {});

/// Checks the invariants every consumer relies on (finite values, unit
/// normals, indices in range, at least one triangle). Throws SceneError.
void validate_mesh(const Mesh& mesh, const MeshLimits& limits = {});

/// For a solid (object.shape "solid"): checks that `mesh` bounds a volume:
/// every edge (by position) is shared by exactly two triangles that run
/// along it in opposite directions, and the enclosed volume is positive
/// (wound outward). Throws SceneError("mesh", ...)
/// counting the offending edges, never naming where they are.
void check_closed(const Mesh& mesh);

/// Area-weighted vertex normals from the faces (winding gives the sign).
/// Vertices on no non-degenerate face get the mean face normal.
std::vector<glm::vec3> smooth_normals(const std::vector<glm::vec3>& positions,
                                      const std::vector<glm::uvec3>& triangles);

/// Writes a mesh as OBJ with `v` (with its colour when tinted), `vn` and
/// `f v//vn` lines; with an atlas (Mesh::uvs), `vt` and `f v/vt/vn`.
void write_obj(const Mesh& mesh, const std::filesystem::path& file);

/// The object's pose resolved against its mesh: everything a renderer needs
/// to take mesh coordinates to the world.
struct Placement {
  glm::dmat4 model{1.0};       ///< mesh -> world (rotation, uniform scale, translation)
  glm::dmat3 rotation{1.0};    ///< rotates mesh normals into the world
  double scale = 1.0;
  glm::dvec3 flat_normal{0, 0, 1};  ///< outward flat-face normal, world
  double flat_offset = 0.0;         ///< flat face: dot(x, flat_normal) = flat_offset, world
  glm::dvec3 center{0, 0, 0};       ///< footprint centre, world (reference for point lights)
  double max_depth = 0.0;           ///< largest depth of a vertex below the flat face, world
  glm::dvec2 footprint{0.0};        ///< extent across the flat-face normal, world units
  /// The slab's bounding box in the world: footprint x [deepest vertex, flat
  /// face]. It is what the public proxy describes, nothing more.
  std::array<glm::dvec3, 8> box{};
};

/// `point` moved along the flat-face normal onto the flat face's plane.
inline glm::dvec3 onto_flat_face(const Placement& p, const glm::dvec3& point) {
  return point + (p.flat_offset - glm::dot(point, p.flat_normal)) * p.flat_normal;
}

/// Rotation matrix of three.js Euler angles in order "XYZ" (degrees): Rx * Ry * Rz.
glm::dmat3 euler_xyz_degrees(const glm::dvec3& degrees);

/// The mesh's extent in the frame of its flat-face normal (e1, e2, normal):
/// all that placing it needs, so a pose changes without a pass over the
/// vertices.
struct MeshBounds {
  glm::dvec3 normal{0, 0, 1};
  glm::dvec3 lo{0.0}, hi{0.0};
};
MeshBounds mesh_bounds(const Mesh& mesh, const glm::dvec3& flat_normal);

/// Resolves fit_size (centring and scaling the footprint perpendicular to the
/// flat-face normal), the default flat-face offset (through the extreme vertex
/// along the normal) and the pose.
Placement place_object(const ObjectParams& object, const Mesh& mesh);
/// The same from bounds taken about object.flat_face_normal (throws
/// std::invalid_argument for bounds about another normal).
Placement place_object(const ObjectParams& object, const MeshBounds& bounds);

/// Rejects configurations the ray model cannot represent: a point light on the
/// flat plane or inside the object, a screen plane that crosses the object, a
/// mesh vertex on the light side of its own flat face. Throws SceneError.
void check_geometry(const Scene& scene, const Mesh& mesh, const Placement& placement);

/// The same checks against the slab's bounding box (Placement::box) instead
/// of the vertices: what a client may be told. Answers that depend on the
/// vertices would let a client map the hidden surface by bisection (its
/// support function, so its convex hull); the box is public anyway. Stricter
/// than check_geometry: whatever passes here passes there. The flat face is
/// not checked: sessions may not move it.
void check_geometry_public(const Scene& scene, const Placement& placement);

}  // namespace caustic
