// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiver with a shape (a vase, a bowl, a column): a triangle mesh in
// world space with a (u, v) atlas in [0, 1]^2. Its light is drawn in (u, v),
// the tile of the picture being that square, so each triangle records how
// much world area a unit of (u, v) covers on it (its stretch): irradiance
// is flux over world area, and a tile's pixel covers the same (u, v) area
// everywhere but not the same world area. Rays find their triangle through
// a bounding volume hierarchy, built once when the scene is read.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace caustic {

struct SurfaceHit {
  double distance = 0;  ///< along the ray (unit direction: world units)
  int element = -1;     ///< the triangle hit
  glm::dvec2 uv{0.0};   ///< its atlas coordinates there
};

class ReceiverMesh {
 public:
  /// Triangles of no world or no (u, v) area are kept out of the hierarchy:
  /// they catch no light (a lathe's pole).
  /// `quad_rows` > 0: the triangles are a grid of quads, two triangles
  /// each, `quad_rows` quads a column (a lathe's).
  ReceiverMesh(std::vector<glm::dvec3> positions, std::vector<glm::dvec2> uvs, std::vector<glm::uvec3> triangles,
               int quad_rows = 0);

  /// The nearest triangle the ray meets at a distance in (0, before).
  std::optional<SurfaceHit> intersect(const glm::dvec3& origin, const glm::dvec3& dir, double before) const;

  /// World area per unit of (u, v) area on triangle `element`.
  double stretch(int element) const { return stretch_[static_cast<std::size_t>(element)]; }

  /// Whether light landing on triangles a and b lies on one continuous
  /// piece of (u, v), close enough that the triangle of the atlas between
  /// the landings stands for the surface between them: on a lathe's grid of
  /// quads, within two quads of each other either way and not across the
  /// seam (the atlas cut open); on any other mesh, one triangle, two
  /// sharing a corner of the atlas, two that a third touches corner to
  /// corner, or two of one piece of the atlas (triangles joined corner to
  /// corner) whose (u, v) centroids lie within kAtlasSpan: a seam of the
  /// atlas splits its corners, so it parts them.
  bool continuous(int a, int b) const;
  /// How far apart in (u, v) two landings on one piece of a mesh's atlas
  /// may lie and still span a triangle of it: an eighth of the atlas, the
  /// width of a ray cell meeting a fine mesh at a grazing angle (on the
  /// gallery's cloth, 0.31 mm of light across 1.5 mm of a far flank).
  static constexpr double kAtlasSpan = 0.125;

  glm::dvec3 lower() const { return lower_; }
  glm::dvec3 upper() const { return upper_; }
  std::size_t triangle_count() const { return triangles_.size(); }

 private:
  struct Node {
    glm::dvec3 lo, hi;
    std::uint32_t first = 0, count = 0;  ///< leaf: a range of order_; inner: count 0, children first, first + 1
  };
  void build(std::uint32_t node, std::uint32_t first, std::uint32_t count, int depth);

  std::vector<glm::dvec3> positions_;
  std::vector<glm::dvec2> uvs_;
  std::vector<glm::uvec3> triangles_;
  std::vector<double> stretch_;
  std::vector<std::uint32_t> order_;  ///< the triangles of the hierarchy, leaf by leaf
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> corner_start_, corner_triangles_;  ///< vertex -> its triangles (not on a lathe)
  std::vector<std::uint32_t> piece_;  ///< triangle -> its piece of the atlas (not on a lathe)
  std::vector<glm::dvec2> uv_centroid_;  ///< triangle -> its (u, v) centroid (not on a lathe)
  glm::dvec3 lower_{0.0}, upper_{0.0};
  int quad_rows_ = 0;
};

/// A surface of revolution: `profile` points (radius >= 0, height along
/// `up`) from `base`, swept round the axis in `segments` steps. (u, v) as
/// three.js's LatheGeometry lays them, so the viewer's copy shows the same
/// atlas: u = i / segments of the turn, starting along `normal` and turning
/// toward up x normal; v = j / (points - 1) along the profile; each quad
/// split as LatheGeometry splits it, so that both draw the same affine map
/// on each triangle. Its seam, u = 0 = 1, cuts the atlas open.
ReceiverMesh make_lathe(const std::vector<glm::dvec2>& profile, int segments, const glm::dvec3& base,
                        const glm::dvec3& normal, const glm::dvec3& up);

}  // namespace caustic
