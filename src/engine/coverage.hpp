// SPDX-License-Identifier: LGPL-2.1-or-later
// Exact pixel coverage of triangles on the CPU, by accumulated signed area:
// the twin of caustic.frag's per-pixel edge integrals, paid per edge rather
// than per pixel. Each edge adds, in every row it crosses, the change along
// x of the area to its right (the integral caustic.frag's edgeCoverage
// takes); a running sum along each row then turns the changes into every
// pixel's covered area, for all triangles at once since the sum is linear.
// A triangle costs the pixels its edges cross, not the pixels it covers,
// and the whole image one pass: on a software renderer, where the fragment
// stage's coverage over each triangle's box bound the caustic, this is a
// fraction of that (docs/performance.md). Accumulated in double so that a
// bright fold's large changes leave no residue along the rest of its row.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace caustic {

class CoverageRaster {
 public:
  /// Starts an empty `width` x `height` image of `channels` (1 or 3) values a pixel.
  void reset(int width, int height, int channels);

  /// Adds `value` (its first `channels` components, each at least 0) times the area of each
  /// pixel that the triangle abc covers, in either winding. Corners are in
  /// pixels, pixel (i, j) spanning [i, i + 1) x [j, j + 1); what falls
  /// outside the image is dropped, and so is a triangle with a corner that
  /// is not finite.
  void triangle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value);

  /// A mesh's triangles (vertex indices) before adding them with
  /// mesh_triangle(): an edge two triangles share is then walked once with
  /// the sum of their values, as an edge's integral only changes sign with
  /// its direction (half the walks of a closed grid). The edge table costs
  /// a pass over the triangles and is kept while they stay the same (a
  /// moving surface keeps its grid); the image depends only on what is
  /// drawn, not on what came before.
  void use_mesh(const std::vector<glm::uvec3>& triangles);

  /// Triangle `t` of the mesh in use, as triangle(); a vertex its triangles
  /// share must come at one position from each.
  void mesh_triangle(std::size_t t, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value);

  /// Adds `value` to the pixel holding `at` (nothing when it is outside).
  void point(glm::dvec2 at, glm::dvec3 value);

  /// Deposits what was added since reset() (on the machine's cores, in
  /// bands of rows) and returns the image, rows from j = 0 up, channels
  /// interleaved.
  const std::vector<float>& resolve();

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }

 private:
  struct Triangle {
    glm::dvec2 a, b, c;
    glm::dvec3 value;  // signed by the winding: the edges' integrals sum to the covered area
  };
  struct Point {
    int i, j;
    glm::dvec3 value;
  };
  template <int N>  // channels
  void edge(glm::dvec2 p, glm::dvec2 q, const glm::dvec3& value, int rows_lo, int rows_hi);
  void band(int lo, int hi);

  int width_ = 0, height_ = 0, channels_ = 1;
  std::vector<Triangle> triangles_;
  std::vector<Point> points_;
  // The mesh in use: its triangles, each side's edge (3 t + k, ~edge when
  // walked against the edge's direction), the edges' vertices (from, to),
  // and this frame's summed values and vertex positions.
  bool mesh_in_use_ = false;
  std::vector<glm::uvec3> mesh_;
  std::vector<std::int32_t> side_edge_;
  std::vector<glm::uvec2> edges_;
  std::vector<glm::dvec3> edge_values_;
  std::vector<glm::dvec2> corners_;
  std::vector<double> changes_;  // per pixel and channel: the covered area's change from the pixel to its left
  std::vector<float> image_;
};

}  // namespace caustic
