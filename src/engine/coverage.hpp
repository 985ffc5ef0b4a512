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

  /// Adds `value` (its first `channels` components) times the area of each
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
  /// drawn, not on what came before. `layers` sets of positions and values
  /// (at least 1), all empty: each may be filled by its own thread at once,
  /// for example a share of the triangles each, or a wavelength each.
  void use_mesh(const std::vector<glm::uvec3>& triangles, int layers = 1);

  /// Triangle `t` of the mesh in use, as triangle(), into `layer`; a vertex
  /// the layer's triangles share must come at one position from each.
  void mesh_triangle(std::size_t t, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value, int layer = 0);

  /// A triangle outside the mesh in use, as triangle(), into `layer`: a
  /// piece of a mesh triangle that was cut up, filled beside the layer's
  /// mesh triangles by the same thread.
  void loose_triangle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value, int layer = 0);

  /// Adds `value` to the pixel holding `at` (nothing when it is outside),
  /// with `layer`'s triangles (another thread's layer may be filled at once).
  void point(glm::dvec2 at, glm::dvec3 value, int layer = 0);

  /// Deposits what was added so far (on the machine's cores, in bands of
  /// rows) and empties the layers for more: after it the mesh in use may
  /// change, or the same mesh come again at other positions (another
  /// wavelength), each adding to the image without a resolve of its own.
  void flush();

  /// Deposits what was added since reset() (flush()) and returns the
  /// image, rows from j = 0 up, channels interleaved. Once after a reset().
  /// When every value added was at least 0, a sum below 0 is rounding and
  /// reads 0; otherwise (a spectral pass's negative weight) it stands.
  /// `rgba`, with three channels: a fourth value of 0 a pixel, the layout a
  /// float RGBA texture takes without a conversion (which costs a software
  /// renderer more than the sums).
  const std::vector<float>& resolve(bool rgba = false);

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
  // The mesh's positions and edge values of one set of its triangles. A
  // cache line of its own: each thread writes its layer's range and flag at
  // every triangle, and a neighbour's writes on the same line stalled the
  // other thread's reads of its own (a third of mesh_triangle's time).
  struct alignas(64) Layer {
    std::vector<glm::dvec2> corners;
    std::vector<glm::dvec3> edge_values;
    std::vector<Point> points;
    std::vector<Triangle> loose;  // loose_triangle()'s
    bool negative = false;  // a value below 0 was added (a spectral weight)
    // Every edge value outside [dirty_lo, dirty_hi) is 0: a band walks and
    // a flush clears only that range. A share of a grid's triangles in
    // order touches about its share of the edges (numbered by their lower
    // vertex), so each layer's walk and clear is its share, not the whole.
    std::size_t dirty_lo = 0, dirty_hi = 0;
  };
  // Rows [lo, hi): cleared when nothing was flushed yet, what was added
  // deposited, then, when `sum`, summed along each row into the image.
  void band(int lo, int hi, bool sum, int out_channels);
  // Every layer's dirty range back to 0, on the machine's cores.
  void clear_edge_values();

  int width_ = 0, height_ = 0, channels_ = 1;
  std::vector<Triangle> triangles_;
  // The mesh in use: its triangles, each side's edge (3 t + k, ~edge when
  // walked against the edge's direction) and the edges' vertices (from,
  // to); the layers in use hold the summed values and vertex positions.
  bool mesh_in_use_ = false;
  std::vector<glm::uvec3> mesh_;
  std::vector<std::int32_t> side_edge_;
  std::vector<glm::uvec2> edges_;
  std::size_t vertices_ = 0;
  std::vector<Layer> layers_;  // kept allocated; the first layers_in_use_ are this mesh's
  int layers_in_use_ = 1;
  bool flushed_ = false;  // changes_ holds deposits: a band adds to its rows rather than clearing them
  bool negative_ = false;  // a value below 0 was added, to triangles_ or flushed: sums are not clamped
  std::vector<double> changes_;  // per pixel and channel: the covered area's change from the pixel to its left
  std::vector<float> image_;
};

}  // namespace caustic
