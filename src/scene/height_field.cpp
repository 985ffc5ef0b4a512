// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/height_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace caustic {
namespace {

// Sample points: about four a triangle, within these bounds, and at most
// kMaxSide along either side of a long, thin footprint (16 MiB of owners
// at the most: a footprint 1 x 1e-14 once asked 2.5 GB).
constexpr double kPointsPerTriangle = 4;
constexpr std::size_t kMinPoints = 1 << 12, kMaxPoints = 1 << 20;
constexpr double kMaxSide = 2048;
// Rows and points walked over all triangles, per sample point: a face of
// long thin triangles (a fan of 100,000 about one vertex walks about 160)
// is still checked within a second; past this it is refused, not slow.
constexpr double kWalkPerPoint = 512;

// Folds up to this share of the footprint pass: the gallery's designed
// faces fold in slivers where the design bends light hardest (0.008% to
// 0.47% of their footprints), light the reference tracer counts once and
// the accuracy figures include; a layer written twice overlaps 100%.
constexpr double kMaxOverlap = 0.02;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

std::string triangle_name(std::uint32_t t) { return "triangle " + std::to_string(std::size_t{t} + 1); }

std::string share_text(std::size_t part, std::size_t whole) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g%%", 100.0 * double(part) / double(std::max<std::size_t>(whole, 1)));
  return text;
}

}  // namespace

void check_height_field(const Mesh& mesh, const glm::dvec3& normal) {
  // Coordinates in the plane of the flat face.
  const glm::dvec3 n = glm::normalize(normal);
  const glm::dvec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                          : glm::cross(n, glm::dvec3(0, 1, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  std::vector<glm::dvec2> flat(mesh.positions.size());
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (std::size_t i = 0; i < flat.size(); ++i) {
    const glm::dvec3 p(mesh.positions[i]);
    flat[i] = {glm::dot(p, u), glm::dot(p, v)};
    lo = glm::min(lo, flat[i]), hi = glm::max(hi, flat[i]);
  }
  const glm::dvec2 extent = hi - lo;
  // Edge-on (a sheet seen along itself, to rounding): no footprint to overlap.
  if (!(std::min(extent.x, extent.y) > 1e-9 * std::max(extent.x, extent.y))) return;
  // Cells over the footprint's box, square but for a side of at most
  // kMaxSide or at least one of them; the sample point of a cell is off
  // its centre by an irrational share, so that a grid's vertices and edges
  // (which lie on round coordinates) do not pass through sample points.
  const double points = std::clamp(kPointsPerTriangle * double(mesh.triangles.size()), double(kMinPoints),
                                   double(kMaxPoints));
  const double side = std::sqrt(extent.x * extent.y / points);
  const auto count = [&](double length) {
    return static_cast<int>(std::clamp(std::ceil(length / side), 1.0, kMaxSide));
  };
  const int columns = count(extent.x), rows = count(extent.y);
  const glm::dvec2 cell(extent.x / columns, extent.y / rows);
  const double offset = 0.5 + 0.01 * (std::sqrt(2.0) - 1.0);
  std::vector<std::uint32_t> owner(static_cast<std::size_t>(columns) * rows, kNone);
  double walked = 0;
  std::size_t covered = 0, overlapping = 0;  // sample points covered once, and again
  std::pair<std::uint32_t, std::uint32_t> first_pair{kNone, kNone};
  const double budget = kWalkPerPoint * double(owner.size()) + 16.0 * double(mesh.triangles.size());
  const auto refuse = [&](bool early) {
    throw SceneError("mesh", triangle_name(first_pair.first) + " and " + triangle_name(first_pair.second) +
                                 " (and more: " + (early ? "at least " + share_text(overlapping, owner.size())
                                                         : share_text(overlapping, covered)) +
                                 " of the face's footprint) overlap seen along the flat face's normal: a slab's "
                                 "caustic face must be a height field over its flat face (one layer, no folds "
                                 "beyond a sliver), or the light through the overlap would be counted twice");
  };

  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::dvec2 a = flat[tri.x], b = flat[tri.y], c = flat[tri.z];
    const double twice_area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (twice_area == 0) continue;  // edge-on (a wall): it covers no point
    const double y_lo = std::min({a.y, b.y, c.y}), y_hi = std::max({a.y, b.y, c.y});
    const int first = std::max(0, static_cast<int>(std::ceil((y_lo - lo.y) / cell.y - offset)));
    const int last = std::min(rows - 1, static_cast<int>(std::floor((y_hi - lo.y) / cell.y - offset)));
    walked += std::max(0, last - first + 1);
    if (walked > budget)
      throw SceneError("mesh", "has too many long, thin triangles to check that it is a height field over its flat "
                               "face: split them");
    for (int j = first; j <= last; ++j) {
      const double y = lo.y + (j + offset) * cell.y;
      // Where the row's line crosses the triangle: between the crossings of
      // the edges that straddle it.
      double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
      for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        if ((p.y > y) == (q.y > y)) continue;
        const double x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
        x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
      }
      if (!(x_lo < x_hi)) continue;
      const int i_lo = std::max(0, static_cast<int>(std::ceil((x_lo - lo.x) / cell.x - offset)));
      const int i_hi = std::min(columns - 1, static_cast<int>(std::floor((x_hi - lo.x) / cell.x - offset)));
      walked += std::max(0, i_hi - i_lo + 1);
      for (int i = i_lo; i <= i_hi; ++i) {
        const double x = lo.x + (i + offset) * cell.x;
        if (!(x > x_lo && x < x_hi)) continue;  // strictly inside: a shared edge's point is no one's
        std::uint32_t& o = owner[static_cast<std::size_t>(j) * columns + i];
        if (o == kNone) {
          o = t, ++covered;
        } else if (o != t) {
          if (overlapping++ == 0) first_pair = {o, t};
          // Past the share of every point there is: refused now, whatever
          // follows (layers stacked by the thousand were walked whole).
          if (overlapping > kMaxOverlap * double(owner.size())) refuse(true);
        }
      }
    }
  }
  if (overlapping > kMaxOverlap * covered) refuse(false);
}

Mesh load_face(const Scene& scene) {
  Mesh mesh = load_obj(scene.mesh_path());
  if (scene.object.shape != Shape::solid) check_height_field(mesh, scene.object.flat_face_normal);
  return mesh;
}

}  // namespace caustic
