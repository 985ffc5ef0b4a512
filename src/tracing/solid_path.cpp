// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/solid_path.hpp"

#include "caustic/optics.hpp"

#include <numeric>

namespace caustic {
namespace {

int find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// FNV-1a step: the signature only has to tell paths apart, not be secret.
std::uint64_t mix(std::uint64_t h, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) h = (h ^ ((value >> (8 * i)) & 0xff)) * 0x100000001b3ull;
  return h;
}

}  // namespace

Solid::Solid(const Mesh& mesh, const Placement& placement) : placement_(placement), geometry_(mesh, placement_) {
  // Surfaces: triangles joined through shared vertex indices (union-find).
  std::vector<int> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& t : mesh.triangles) {
    const int a = find(parent, static_cast<int>(t.x));
    parent[find(parent, static_cast<int>(t.y))] = a;
    parent[find(parent, static_cast<int>(t.z))] = a;
  }
  std::vector<int> label(mesh.positions.size(), -1);
  surface_.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    int& l = label[static_cast<std::size_t>(find(parent, static_cast<int>(t.x)))];
    if (l < 0) l = surfaces_++;
    surface_.push_back(l);
  }
  glm::dvec3 lo(1e300), hi(-1e300);
  points_.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    points_.push_back(geometry_.world(i));
    lo = glm::min(lo, points_.back());
    hi = glm::max(hi, points_.back());
  }
  if (!mesh.positions.empty()) {
    extent_ = std::max(0.5 * glm::length(hi - lo), 1e-9);
    centre_ = 0.5 * (lo + hi);
  }
}

SolidPath follow_solid(const Solid& solid, glm::dvec3 origin, glm::dvec3 dir, double ior, bool fresnel,
                       FresnelSplit split, std::mt19937_64* rng) {
  using namespace optics;
  SolidPath path;
  // Far below the thinnest sensible wall, far above float rounding of a hit.
  const double nudge = 2e-6 * solid.extent();
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Geometry::Hit hit;
  while (solid.geometry().intersect(origin, dir, 0.0, &hit)) {
    if (++path.events > kMaxSolidEvents) return path;  // trapped: dropped
    const bool entering = glm::dot(dir, hit.facet) < 0;
    const double n1 = entering ? 1.0 : ior, n2 = entering ? ior : 1.0;
    const glm::dvec3 normal = face_against(hit.normal, dir);
    const auto refracted = refract(dir, normal, n1 / n2);
    bool reflect_here = !refracted;  // TIR: all of it reflects
    if (refracted && fresnel) {
      const double t = fresnel_transmittance(refracted->cos_i, n1, n2);
      if (split == FresnelSplit::weight) path.transmittance *= t;
      else reflect_here = uniform(*rng) >= t;
    }
    dir = reflect_here ? glm::normalize(optics::reflect(dir, normal)) : refracted->direction;
    if (!reflect_here) path.tint *= hit.tint;  // a tint filters what crosses the face
    path.signature = mix(mix(path.signature, static_cast<std::uint64_t>(solid.surface(hit.triangle))),
                         (entering ? 2u : 0u) + (reflect_here ? 1u : 0u));
    // Off the face on the side the ray now travels to (by the facet, which
    // the next hit's inside/outside test reads too).
    origin = hit.point + (glm::dot(dir, hit.facet) > 0 ? nudge : -nudge) * hit.facet;
  }
  path.valid = path.events > 0;  // a ray that never met the glass is not its light
  path.origin = origin;
  path.dir = dir;
  return path;
}

}  // namespace caustic
