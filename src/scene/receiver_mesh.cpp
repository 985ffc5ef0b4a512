// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/receiver_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace caustic {
namespace {

constexpr std::uint32_t kLeafSize = 4;

double triangle_area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

double uv_area(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const glm::dvec2 e1 = b - a, e2 = c - a;
  return 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x);
}

// Where the ray enters the box, if it does before `before` (slabs; an axis
// the ray runs along gives infinities that compare correctly); else infinity.
double entry(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& origin, const glm::dvec3& inverse,
             double before) {
  double near = 0, far = before;
  for (int k = 0; k < 3; ++k) {
    double t0 = (lo[k] - origin[k]) * inverse[k], t1 = (hi[k] - origin[k]) * inverse[k];
    if (t0 > t1) std::swap(t0, t1);
    if (std::isnan(t0) || std::isnan(t1)) continue;  // origin on a slab of a flat box, ray along it
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far ? near : std::numeric_limits<double>::infinity();
}

}  // namespace

ReceiverMesh::ReceiverMesh(std::vector<glm::dvec3> positions, std::vector<glm::dvec2> uvs,
                           std::vector<glm::uvec3> triangles, int quad_rows)
    : positions_(std::move(positions)), uvs_(std::move(uvs)), triangles_(std::move(triangles)), quad_rows_(quad_rows) {
  stretch_.resize(triangles_.size(), 0.0);
  lower_ = glm::dvec3(std::numeric_limits<double>::infinity());
  upper_ = -lower_;
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    const glm::uvec3 v = triangles_[t];
    const double world = triangle_area(positions_[v.x], positions_[v.y], positions_[v.z]);
    const double flat = uv_area(uvs_[v.x], uvs_[v.y], uvs_[v.z]);
    if (!(world > 0) || !(flat > 0)) continue;
    stretch_[t] = world / flat;
    order_.push_back(t);
    for (int k = 0; k < 3; ++k) {
      lower_ = glm::min(lower_, positions_[v[k]]);
      upper_ = glm::max(upper_, positions_[v[k]]);
    }
  }
  if (quad_rows_ == 0) {  // the triangles round each vertex, for continuous()
    corner_start_.assign(positions_.size() + 1, 0);
    for (const glm::uvec3& v : triangles_)
      for (int k = 0; k < 3; ++k) ++corner_start_[v[k] + 1];
    for (std::size_t i = 1; i < corner_start_.size(); ++i) corner_start_[i] += corner_start_[i - 1];
    corner_triangles_.resize(corner_start_.back());
    std::vector<std::uint32_t> filled(corner_start_.begin(), corner_start_.end() - 1);
    for (std::uint32_t t = 0; t < triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) corner_triangles_[filled[triangles_[t][k]]++] = t;
    // Pieces: vertices joined by triangles (union-find, halving paths).
    std::vector<std::uint32_t> parent(positions_.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    const auto root = [&](std::uint32_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (const glm::uvec3& v : triangles_) {
      parent[root(v.y)] = root(v.x);
      parent[root(v.z)] = root(v.x);
    }
    piece_.resize(triangles_.size());
    uv_centroid_.resize(triangles_.size());
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const glm::uvec3 v = triangles_[t];
      piece_[t] = root(v.x);
      uv_centroid_[t] = (uvs_[v.x] + uvs_[v.y] + uvs_[v.z]) / 3.0;
    }
  }
  if (order_.empty()) return;
  nodes_.reserve(2 * order_.size() / kLeafSize + 2);
  nodes_.resize(1);
  build(0, 0, static_cast<std::uint32_t>(order_.size()), 0);
}

// Fills node `node` with the triangles order_[first, first + count).
void ReceiverMesh::build(std::uint32_t node, std::uint32_t first, std::uint32_t count, int depth) {
  const auto centroid = [&](std::uint32_t t) {
    const glm::uvec3 v = triangles_[t];
    return (positions_[v.x] + positions_[v.y] + positions_[v.z]) / 3.0;
  };
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo), clo = lo, chi = hi;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const glm::uvec3 v = triangles_[order_[i]];
    for (int k = 0; k < 3; ++k) lo = glm::min(lo, positions_[v[k]]), hi = glm::max(hi, positions_[v[k]]);
    clo = glm::min(clo, centroid(order_[i]));
    chi = glm::max(chi, centroid(order_[i]));
  }
  nodes_[node] = {lo, hi, first, count};
  // Depth bounded: many triangles about one centroid stay one long leaf.
  if (count <= kLeafSize || depth > 48) return;
  const glm::dvec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](std::uint32_t a, std::uint32_t b) { return centroid(a)[axis] < centroid(b)[axis]; });
  const auto children = static_cast<std::uint32_t>(nodes_.size());
  nodes_.resize(nodes_.size() + 2);
  nodes_[node].first = children;
  nodes_[node].count = 0;
  build(children, first, half, depth + 1);
  build(children + 1, first + half, count - half, depth + 1);
}

std::optional<SurfaceHit> ReceiverMesh::intersect(const glm::dvec3& origin, const glm::dvec3& dir,
                                                  double before) const {
  if (nodes_.empty()) return std::nullopt;
  const glm::dvec3 inverse = 1.0 / dir;
  std::optional<SurfaceHit> best;
  struct Pending {
    std::uint32_t node;
    double entry;  // where the ray enters its box: skipped once a hit lies nearer
  };
  Pending stack[64];
  int top = 0;
  stack[top++] = {0, entry(nodes_[0].lo, nodes_[0].hi, origin, inverse, before)};
  while (top > 0) {
    const Pending p = stack[--top];
    if (!(p.entry < before)) continue;
    const Node& n = nodes_[p.node];
    if (n.count == 0) {
      // The nearer child on top: its hit shortens the search of the other.
      const double ta = entry(nodes_[n.first].lo, nodes_[n.first].hi, origin, inverse, before);
      const double tb = entry(nodes_[n.first + 1].lo, nodes_[n.first + 1].hi, origin, inverse, before);
      const Pending a{n.first, ta}, b{n.first + 1, tb};
      stack[top++] = ta <= tb ? b : a;
      stack[top++] = ta <= tb ? a : b;
      continue;
    }
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
      // Moller-Trumbore in double precision.
      const glm::uvec3 v = triangles_[order_[i]];
      const glm::dvec3 p0 = positions_[v.x], e1 = positions_[v.y] - p0, e2 = positions_[v.z] - p0;
      const glm::dvec3 pv = glm::cross(dir, e2);
      const double det = glm::dot(e1, pv);
      if (!(std::abs(det) > 0)) continue;
      const glm::dvec3 tv = origin - p0;
      const double b1 = glm::dot(tv, pv) / det;
      if (b1 < 0 || b1 > 1) continue;
      const glm::dvec3 qv = glm::cross(tv, e1);
      const double b2 = glm::dot(dir, qv) / det;
      if (b2 < 0 || b1 + b2 > 1) continue;
      const double t = glm::dot(e2, qv) / det;
      if (!(t > 0) || !(t < before)) continue;
      before = t;
      const glm::dvec2 uv = (1 - b1 - b2) * uvs_[v.x] + b1 * uvs_[v.y] + b2 * uvs_[v.z];
      best = SurfaceHit{t, static_cast<int>(order_[i]), uv};
    }
  }
  return best;
}

bool ReceiverMesh::continuous(int a, int b) const {
  if (a == b) return true;
  if (quad_rows_ > 0) {
    const int qa = a / 2, qb = b / 2;
    return std::abs(qa / quad_rows_ - qb / quad_rows_) <= 2 && std::abs(qa % quad_rows_ - qb % quad_rows_) <= 2;
  }
  const auto touches = [](const glm::uvec3& x, const glm::uvec3& y) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (x[i] == y[j]) return true;
    return false;
  };
  const glm::uvec3 x = triangles_[static_cast<std::size_t>(a)], y = triangles_[static_cast<std::size_t>(b)];
  if (touches(x, y)) return true;
  for (int i = 0; i < 3; ++i)
    for (std::uint32_t k = corner_start_[x[i]]; k < corner_start_[x[i] + 1]; ++k)
      if (touches(triangles_[corner_triangles_[k]], y)) return true;
  const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
  return piece_[i] == piece_[j] && glm::length(uv_centroid_[i] - uv_centroid_[j]) <= kAtlasSpan;
}

ReceiverMesh make_lathe(const std::vector<glm::dvec2>& profile, int segments, const glm::dvec3& base,
                        const glm::dvec3& normal, const glm::dvec3& up) {
  const glm::dvec3 right = glm::normalize(glm::cross(up, normal));
  const auto rows = static_cast<std::uint32_t>(profile.size());
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec2> uvs;
  for (int i = 0; i <= segments; ++i) {
    const double u = static_cast<double>(i) / segments, phi = 2 * std::numbers::pi * u;
    // The seam's two columns are one circle: the same points, exactly.
    const double s = i == segments ? 0.0 : std::sin(phi), c = i == segments ? 1.0 : std::cos(phi);
    for (std::uint32_t j = 0; j < rows; ++j) {
      const glm::dvec2 p = profile[j];
      positions.push_back(base + p.x * s * right + p.y * up + p.x * c * normal);
      uvs.emplace_back(u, rows > 1 ? static_cast<double>(j) / (rows - 1) : 0.0);
    }
  }
  std::vector<glm::uvec3> triangles;
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(segments); ++i)
    for (std::uint32_t j = 0; j + 1 < rows; ++j) {
      const std::uint32_t a = i * rows + j, b = (i + 1) * rows + j, c = (i + 1) * rows + j + 1, d = i * rows + j + 1;
      triangles.emplace_back(a, b, d);
      triangles.emplace_back(c, d, b);
    }
  return ReceiverMesh(std::move(positions), std::move(uvs), std::move(triangles), static_cast<int>(rows) - 1);
}

}  // namespace caustic
