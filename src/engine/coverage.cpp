// SPDX-License-Identifier: LGPL-2.1-or-later
#include "coverage.hpp"

#include "bands.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustic {
namespace {

// Pixel coordinates beyond this are dropped: they keep floor_int in range
// (the caustic pass drops triangles wider than 64 targets long before).
constexpr double kLimit = 1e8;

bool usable(glm::dvec2 p) { return std::abs(p.x) < kLimit && std::abs(p.y) < kLimit; }  // false for NaN

// floor() for |x| < 2^31 without a library call (the build targets plain SSE2).
int floor_int(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i ? 1 : 0);
}

// Mean of clamp(t, 0, 1) for t running linearly from u0 to u1 (caustic.frag's
// meanRamp), every term scaling with |u1 - u0|: no cancellation for steep edges.
double mean_ramp(double u0, double u1) {
  const double lo = std::min(u0, u1), hi = std::max(u0, u1);
  if (hi - lo < 1e-12) return std::clamp(0.5 * (lo + hi), 0.0, 1.0);
  const double cl = std::clamp(lo, 0.0, 1.0), ch = std::clamp(hi, 0.0, 1.0);
  return (0.5 * (ch - cl) * (ch + cl) + (std::max(hi, 1.0) - std::max(lo, 1.0))) / (hi - lo);
}

// The integral from -inf to t of the hat max(0, 1 - |s|): the share of a
// unit of x, spread uniformly up to t, that pixel i takes of the change
// f(i) - f(i - 1) when t is measured from i.
double hat_integral(double t) {
  if (t <= -1) return 0;
  if (t < 0) return 0.5 * (t + 1) * (t + 1);
  if (t < 1) return 1 - 0.5 * (1 - t) * (1 - t);
  return 1;
}

// Below this width in x an edge's part in a row counts as vertical, at its
// mean x: the coverage it misplaces is at most this share of the row's height.
constexpr double kVertical = 1e-7;

// Rows per band at the least: a thread costs more than a thin band saves.
constexpr int kMinBandRows = 64;
// Edges per share of a clear at the least, likewise.
constexpr int kMinClearEdges = 16384;

}  // namespace

void CoverageRaster::reset(int width, int height, int channels) {
  width_ = std::max(width, 0);
  height_ = std::max(height, 0);
  channels_ = channels == 3 ? 3 : 1;
  changes_.resize(static_cast<std::size_t>(width_) * height_ * channels_);
  triangles_.clear();
  if (layers_.empty()) layers_.resize(1);
  layers_in_use_ = 1;
  layers_[0].points.clear();
  layers_[0].loose.clear();
  layers_[0].negative = false;
  mesh_in_use_ = false;
  flushed_ = negative_ = false;
}

void CoverageRaster::use_mesh(const std::vector<glm::uvec3>& triangles, int layers) {
  if (triangles != mesh_ || side_edge_.size() != 3 * triangles.size()) {
    mesh_ = triangles;
    // Sides bucketed by their lower vertex (a counting sort, linear in the
    // sides): within a bucket of a few, equal upper vertices are one edge.
    const std::size_t sides = 3 * triangles.size();
    auto side_from = [&](std::size_t side) { return mesh_[side / 3][side % 3]; };
    auto side_to = [&](std::size_t side) { return mesh_[side / 3][(side % 3 + 1) % 3]; };
    std::uint32_t top = 0;
    for (const glm::uvec3& t : triangles) top = std::max({top, t.x, t.y, t.z});
    const std::size_t vertices = vertices_ = triangles.empty() ? 0 : std::size_t{top} + 1;
    std::vector<std::uint32_t> start(vertices + 1, 0), order(sides);
    for (std::size_t side = 0; side < sides; ++side) ++start[std::min(side_from(side), side_to(side)) + 1];
    for (std::size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t side = 0; side < sides; ++side)
      order[next[std::min(side_from(side), side_to(side))]++] = static_cast<std::uint32_t>(side);
    side_edge_.assign(sides, 0);
    edges_.clear();
    for (std::size_t v = 0; v < vertices; ++v)
      for (std::uint32_t n = start[v]; n < start[v + 1]; ++n) {
        const std::uint32_t side = order[n], from = side_from(side), to = side_to(side);
        std::int32_t e = -1;
        for (std::uint32_t m = start[v]; m < n && e < 0; ++m) {  // an earlier side of this edge
          const std::uint32_t other = order[m];
          if (std::max(side_from(other), side_to(other)) != std::max(from, to)) continue;
          e = side_edge_[other] >= 0 ? side_edge_[other] : ~side_edge_[other];
        }
        if (e < 0) {
          e = static_cast<std::int32_t>(edges_.size());
          edges_.push_back({from, to});
        }
        side_edge_[side] = from == edges_[e].x ? e : ~e;
      }
  }
  layers_in_use_ = std::max(layers, 1);
  if (layers_.size() < static_cast<std::size_t>(layers_in_use_)) layers_.resize(static_cast<std::size_t>(layers_in_use_));
  for (int k = 0; k < layers_in_use_; ++k) {
    Layer& layer = layers_[static_cast<std::size_t>(k)];
    layer.corners.resize(vertices_);
    if (layer.edge_values.size() != edges_.size()) {
      layer.edge_values.assign(edges_.size(), glm::dvec3(0));
      layer.dirty_lo = layer.dirty_hi = 0;
    }
    if (k > 0) layer.points.clear(), layer.loose.clear(), layer.negative = false;  // layer 0's may hold what point() added
  }
  // A flush leaves the values it walked at 0: only a layer resolved without
  // one (the last of a frame) still holds them.
  clear_edge_values();
  mesh_in_use_ = true;
}

void CoverageRaster::clear_edge_values() {
  std::size_t dirty = 0;
  for (Layer& layer : layers_) {
    // A layer left from another edge table is emptied (use_mesh() sizes it
    // again when it comes into use): no range of it outlives its table.
    if (layer.edge_values.size() != edges_.size()) layer.edge_values.clear(), layer.dirty_lo = layer.dirty_hi = 0;
    dirty += layer.dirty_hi - layer.dirty_lo;
  }
  if (dirty == 0) return;
  // A share of the edges a core (24 bytes an edge a layer: megabytes a
  // pass at a 256² mesh).
  in_bands(static_cast<int>(edges_.size()), kMinClearEdges, [this](int lo, int hi) {
    for (Layer& layer : layers_) {
      const std::size_t from = std::max<std::size_t>(layer.dirty_lo, lo), to = std::min<std::size_t>(layer.dirty_hi, hi);
      if (from < to)
        std::fill(layer.edge_values.begin() + from, layer.edge_values.begin() + to, glm::dvec3(0));
    }
  });
  for (Layer& layer : layers_) layer.dirty_lo = layer.dirty_hi = 0;
}

void CoverageRaster::mesh_triangle(std::size_t t, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value,
                                   int layer) {
  if (!usable(a) || !usable(b) || !usable(c) || width_ == 0 || height_ == 0) return;
  const double twice_area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  const glm::dvec3 signed_value = twice_area > 0 ? -value : value;  // as triangle()
  const glm::uvec3& corners = mesh_[t];
  Layer& l = layers_[static_cast<std::size_t>(layer)];
  l.negative = l.negative || glm::any(glm::lessThan(value, glm::dvec3(0)));
  l.corners[corners.x] = a, l.corners[corners.y] = b, l.corners[corners.z] = c;
  std::size_t lo = l.dirty_lo, hi = l.dirty_hi;
  if (lo == hi) lo = std::numeric_limits<std::size_t>::max(), hi = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int32_t e = side_edge_[3 * t + k];
    const std::size_t index = static_cast<std::size_t>(e >= 0 ? e : ~e);
    if (e >= 0) l.edge_values[index] += signed_value;
    else l.edge_values[index] -= signed_value;
    lo = std::min(lo, index), hi = std::max(hi, index + 1);
  }
  l.dirty_lo = lo, l.dirty_hi = hi;
}

void CoverageRaster::triangle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value) {
  if (!usable(a) || !usable(b) || !usable(c) || width_ == 0 || height_ == 0) return;
  // The edges' integrals sum to minus the covered area for a counter-
  // clockwise triangle, plus for a clockwise one.
  const double twice_area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  triangles_.push_back({a, b, c, twice_area > 0 ? -value : value});
  negative_ = negative_ || glm::any(glm::lessThan(value, glm::dvec3(0)));
}

void CoverageRaster::loose_triangle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec3 value, int layer) {
  if (!usable(a) || !usable(b) || !usable(c) || width_ == 0 || height_ == 0) return;
  const double twice_area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  Layer& l = layers_[static_cast<std::size_t>(layer)];
  l.loose.push_back({a, b, c, twice_area > 0 ? -value : value});
  l.negative = l.negative || glm::any(glm::lessThan(value, glm::dvec3(0)));
}

void CoverageRaster::point(glm::dvec2 at, glm::dvec3 value, int layer) {
  if (!usable(at)) return;
  const int i = floor_int(at.x), j = floor_int(at.y);
  if (i < 0 || j < 0 || i >= width_ || j >= height_) return;
  Layer& l = layers_[static_cast<std::size_t>(layer)];
  l.negative = l.negative || glm::any(glm::lessThan(value, glm::dvec3(0)));
  l.points.push_back({i, j, value});
}

// In each row of [rows_lo, rows_hi) the edge crosses: the integral over its
// part within the row of the width of pixel i to its right, f(i)
// (caustic.frag's edgeCoverage, signed by the edge's direction in y),
// stored as f(i) - f(i - 1). f is 0 left of the edge and the row's whole
// signed height right of it, so only the pixels the edge spans, and the one
// after, change; a part left of the image counts in pixel 0, a part right
// of it nowhere.
template <int N>
void CoverageRaster::edge(glm::dvec2 p, glm::dvec2 q, const glm::dvec3& value, int rows_lo, int rows_hi) {
  if (p.y == q.y) return;
  const double direction = q.y > p.y ? 1.0 : -1.0;
  if (q.y < p.y) std::swap(p, q);
  if (q.y <= rows_lo || p.y >= rows_hi) return;
  const double slope = (q.x - p.x) / (q.y - p.y);
  const int first_row = std::max(rows_lo, floor_int(p.y));
  const int last_row = std::min(rows_hi - 1, floor_int(q.y));
  double y0 = std::max(p.y, double(first_row)), x0 = p.x + (y0 - p.y) * slope;
  for (int j = first_row; j <= last_row; ++j) {
    const double y1 = std::min(q.y, double(j + 1)), x1 = p.x + (y1 - p.y) * slope;
    const double height = direction * (y1 - y0);
    const double xa = x0, xb = x1;
    y0 = y1, x0 = x1;  // the next row starts where this one ends
    double lo = std::min(xa, xb), hi = std::max(xa, xb);
    if (!(height != 0) || lo >= width_) continue;
    double* row = &changes_[static_cast<std::size_t>(j) * width_ * N];
    auto add = [&](int i, double weight) {
      for (int k = 0; k < N; ++k) row[i * N + k] += weight * value[k];
    };
    if (hi - lo < kVertical) lo = hi = 0.5 * (xa + xb);
    const int left = floor_int(lo), right = floor_int(hi);
    if (left == right && left >= 0) {
      // Within one pixel, the common case for a steep edge: the width to
      // its right averages left + 1 - (xa + xb) / 2, and every pixel after
      // gets the whole height.
      const double f = height * (left + 1 - 0.5 * (lo + hi));
      add(left, f);
      if (left + 1 < width_) add(left + 1, height - f);
      continue;
    }
    // Across several pixels: f(i) - f(i - 1) is the height per unit of x
    // times the integral of the hat centred on i over [lo, hi], the whole
    // height per unit of x where the edge crosses pixels i - 1 and i both.
    // A part left of the image: pixel 0 takes f(0) whole.
    int i = std::max(0, left);
    if (left < 0) add(i++, height * mean_ramp(1 - xa, 1 - xb));
    const int last = std::min(width_ - 1, right + 1);
    const double per_x = height / (hi - lo);
    for (; i <= last; ++i) add(i, per_x * (hat_integral(hi - i) - hat_integral(lo - i)));
  }
}

// One band of rows [lo, hi): cleared unless a flush already deposited in
// it, every edge and point that falls in it deposited, then, when `sum`,
// summed along each row into the image.
void CoverageRaster::band(int lo, int hi, bool sum, int out_channels) {
  const std::size_t row = static_cast<std::size_t>(width_) * channels_;
  if (!flushed_) std::fill(changes_.begin() + lo * row, changes_.begin() + hi * row, 0.0);
  const auto walk = [&](const std::vector<Triangle>& triangles) {
    for (const Triangle& t : triangles) {
      if (std::max({t.a.y, t.b.y, t.c.y}) <= lo || std::min({t.a.y, t.b.y, t.c.y}) >= hi) continue;  // another band's
      if (channels_ == 1) {
        edge<1>(t.a, t.b, t.value, lo, hi), edge<1>(t.b, t.c, t.value, lo, hi), edge<1>(t.c, t.a, t.value, lo, hi);
      } else {
        edge<3>(t.a, t.b, t.value, lo, hi), edge<3>(t.b, t.c, t.value, lo, hi), edge<3>(t.c, t.a, t.value, lo, hi);
      }
    }
  };
  walk(triangles_);
  for (int k = 0; k < layers_in_use_; ++k) {
    const Layer& layer = layers_[static_cast<std::size_t>(k)];
    walk(layer.loose);
    if (mesh_in_use_)
      for (std::size_t e = layer.dirty_lo; e < layer.dirty_hi; ++e) {
        const glm::dvec3& value = layer.edge_values[e];
        if (value == glm::dvec3(0)) continue;  // no triangle of the layer beside it, or two that cancel
        const glm::dvec2 p = layer.corners[edges_[e].x], q = layer.corners[edges_[e].y];
        if (channels_ == 1) edge<1>(p, q, value, lo, hi);
        else edge<3>(p, q, value, lo, hi);
      }
    for (const Point& p : layer.points) {
      if (p.j < lo || p.j >= hi) continue;
      double* cell = &changes_[(static_cast<std::size_t>(p.j) * width_ + p.i) * channels_];
      for (int c = 0; c < channels_; ++c) {
        cell[c] += p.value[c];
        if (p.i + 1 < width_) cell[channels_ + c] -= p.value[c];
      }
    }
  }
  if (!sum) return;
  // When every value added is at least 0, a sum below 0 is rounding (a
  // residue of ~1e-16 times the brightest value the row crossed), and 0.
  bool negative = negative_;
  for (int k = 0; k < layers_in_use_; ++k) negative = negative || layers_[static_cast<std::size_t>(k)].negative;
  const double floor = negative ? -std::numeric_limits<double>::infinity() : 0.0;
  for (int j = lo; j < hi; ++j) {
    const double* changes = &changes_[j * row];
    float* out = &image_[static_cast<std::size_t>(j) * width_ * out_channels];
    if (channels_ == 1) {
      double total = 0;
      for (std::size_t n = 0; n < row; ++n) out[n] = static_cast<float>(std::max(total += changes[n], floor));
      continue;
    }
    double total[3] = {0, 0, 0};
    for (std::size_t n = 0, o = 0; n < row; n += 3, o += out_channels) {
      for (int c = 0; c < 3; ++c) out[o + c] = static_cast<float>(std::max(total[c] += changes[n + c], floor));
      if (out_channels == 4) out[o + 3] = 0.0f;
    }
  }
}

void CoverageRaster::flush() {
  // Each band walks every edge but touches only its own rows.
  in_bands(height_, kMinBandRows, [this](int lo, int hi) { band(lo, hi, false, channels_); });
  flushed_ = true;
  triangles_.clear();
  for (int k = 0; k < layers_in_use_; ++k) {
    Layer& layer = layers_[static_cast<std::size_t>(k)];
    negative_ = negative_ || layer.negative;
    layer.negative = false;
    layer.points.clear();
    layer.loose.clear();
  }
  // The values walked, cleared for the next pass.
  if (mesh_in_use_) clear_edge_values();
}

const std::vector<float>& CoverageRaster::resolve(bool rgba) {
  const int out = rgba && channels_ == 3 ? 4 : channels_;
  image_.resize(static_cast<std::size_t>(width_) * height_ * out);
  in_bands(height_, kMinBandRows, [this, out](int lo, int hi) { band(lo, hi, true, out); });
  return image_;
}

}  // namespace caustic
