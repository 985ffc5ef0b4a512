// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/vertex_rays.hpp"

#include "caustic/optics.hpp"

#include <cmath>
#include <limits>

namespace caustic {

namespace {

// A slab's glass lies on the flat face's side of its caustic face. A ray
// that would meet the face at v from the wrong side (the light outside
// arriving from within the glass, or the light inside from without) has
// crossed the face elsewhere first: v lies in the face's own shadow, and
// counting it would count the light that crossed there a second time.
bool meets_face_from_wrong_side(const glm::dvec3& ray, const glm::dvec3& n, const glm::dvec3& flat_normal, bool inside) {
  const double side = glm::dot(ray, n) * glm::dot(flat_normal, n);
  return inside ? side > 0.0 : side < 0.0;
}

// `mesh`'s vertex i placed in the world, and its normal turned with it.
struct PlacedVertex {
  glm::dvec3 v, n;
};
PlacedVertex placed_vertex(const Placement& placement, const Mesh& mesh, std::size_t i) {
  return {glm::dvec3(placement.model * glm::dvec4(glm::dvec3(mesh.positions[i]), 1.0)),
          glm::normalize(placement.rotation * glm::dvec3(mesh.normals[i]))};
}

}  // namespace

bool flat_face_first(const Scene& scene, const Placement& placement) {
  if (scene.object.shape == Shape::surface) return false;  // the light meets the surface, whichever side
  if (scene.light.type == LightType::point)
    return glm::dot(scene.light.position, placement.flat_normal) > placement.flat_offset;
  return glm::dot(scene.light.direction, placement.flat_normal) < 0.0;
}

ExitRay exit_ray(const Scene& scene, const Placement& placement, double ior, const glm::dvec3& v, const glm::dvec3& n) {
  using namespace optics;
  const bool point = scene.light.type == LightType::point;
  const Plane flat{placement.flat_normal, placement.flat_offset};
  ExitRay ray;
  ray.footprint = v;
  Vec3 incident = point ? glm::normalize(v - scene.light.position) : scene.light.direction;
  Vec3 origin = v, dir;
  double t = 1.0;

  if (scene.object.material == Material::reflective) {
    dir = reflect(incident, face_against(n, incident));
  } else if (flat_face_first(scene, placement)) {
    const bool exact = point && scene.light.point_model == PointModel::exact;
    if (exact) {
      const auto entry = point_light_entry(scene.light.position, v, flat, ior);
      if (!entry) return ray;
      ray.footprint = *entry;
      incident = glm::normalize(*entry - scene.light.position);
    }
    const auto in = refract(incident, face_against(flat.normal, incident), 1.0 / ior);
    if (!in) return ray;
    t *= fresnel_transmittance(in->cos_i, 1.0, ior);
    const Vec3 inside = exact ? glm::normalize(v - ray.footprint) : in->direction;
    if (meets_face_from_wrong_side(inside, n, flat.normal, true)) {
      ray.shaded = true;
      return ray;
    }
    if (!exact) ray.footprint = v + inside * (-flat.signed_distance(v) / glm::dot(inside, flat.normal));
    const auto out = refract(inside, face_against(n, inside), ior);
    if (!out) return ray;
    t *= fresnel_transmittance(out->cos_i, ior, 1.0);
    dir = out->direction;
  } else {
    if (scene.object.shape != Shape::surface && meets_face_from_wrong_side(incident, n, flat.normal, false)) {
      ray.shaded = true;
      return ray;
    }
    const auto in = refract(incident, face_against(n, incident), 1.0 / ior);
    if (!in) return ray;
    t *= fresnel_transmittance(in->cos_i, 1.0, ior);
    dir = in->direction;
    if (scene.object.shape != Shape::surface) {  // a slab's light leaves by the flat face; a surface's stays in
      const double toward = glm::dot(in->direction, flat.normal);
      if (!(toward > 1e-6)) return ray;
      origin = v + in->direction * (-flat.signed_distance(v) / toward);
      const auto out = refract(in->direction, face_against(flat.normal, in->direction), ior);
      if (!out) return ray;
      t *= fresnel_transmittance(out->cos_i, ior, 1.0);
      dir = out->direction;
    }
  }
  ray.valid = true;
  ray.origin = origin;
  ray.direction = dir;
  ray.transmittance = scene.render.fresnel ? t : 1.0;
  return ray;
}

double self_shaded_share(const Scene& scene, const Placement& placement, const Mesh& mesh) {
  if (scene.object.material == Material::reflective || scene.object.shape != Shape::slab || mesh.positions.empty())
    return 0.0;
  std::size_t shaded = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto [v, n] = placed_vertex(placement, mesh, i);
    if (exit_ray(scene, placement, scene.object.ior, v, n).shaded) ++shaded;
  }
  return static_cast<double>(shaded) / static_cast<double>(mesh.positions.size());
}

VertexRay trace_vertex(const Scene& scene, const Placement& placement, const glm::dvec3& v, const glm::dvec3& n) {
  const ExitRay exit = exit_ray(scene, placement, scene.object.ior, v, n);
  VertexRay ray;
  ray.footprint = exit.footprint;
  if (!exit.valid) return ray;
  const auto& screen = scene.screen;
  const double denom = glm::dot(exit.direction, screen.normal);
  if (!(std::abs(denom) > 1e-6)) return ray;
  const double s = glm::dot(screen.center - exit.origin, screen.normal) / denom;
  if (!(s > 0.0) || !std::isfinite(s)) return ray;
  const glm::dvec3 hit = exit.origin + s * exit.direction - screen.center;
  ray.screen = {glm::dot(hit, screen_right(screen)), glm::dot(hit, screen.up)};
  ray.transmittance = exit.transmittance;
  ray.valid = true;
  return ray;
}

double reference_distance2(const Scene& scene, const Placement& placement) {
  const glm::dvec3 d = scene.light.position - placement.center;
  return glm::dot(d, d);
}

double triangle_flux(const Scene& scene, const Placement& placement, const VertexRay& a, const VertexRay& b,
                     const VertexRay& c) {
  const double t = (a.transmittance + b.transmittance + c.transmittance) / 3.0;
  if (scene.light.type == LightType::point) {
    return t * reference_distance2(scene, placement) *
           optics::solid_angle(scene.light.position, a.footprint, b.footprint, c.footprint);
  }
  const glm::dvec3 area_vector = 0.5 * glm::cross(b.footprint - a.footprint, c.footprint - a.footprint);
  return t * std::abs(glm::dot(area_vector, scene.light.direction));
}

FluxSummary summarize_flux(const Scene& scene, const Mesh& mesh, const Placement& placement) {
  std::vector<VertexRay> rays(mesh.positions.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto [v, n] = placed_vertex(placement, mesh, i);
    rays[i] = trace_vertex(scene, placement, v, n);
  }
  FluxSummary sum;
  sum.screen_min = glm::dvec2(std::numeric_limits<double>::infinity());
  sum.screen_max = -sum.screen_min;
  for (const auto& tri : mesh.triangles) {
    const VertexRay &a = rays[tri.x], &b = rays[tri.y], &c = rays[tri.z];
    if (!a.valid || !b.valid || !c.valid) continue;
    sum.flux += triangle_flux(scene, placement, a, b, c);
    ++sum.valid_triangles;
    for (const auto* r : {&a, &b, &c}) {
      sum.screen_min = glm::min(sum.screen_min, r->screen);
      sum.screen_max = glm::max(sum.screen_max, r->screen);
    }
  }
  return sum;
}

}  // namespace caustic
