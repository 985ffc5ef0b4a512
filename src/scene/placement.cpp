// SPDX-License-Identifier: LGPL-2.1-or-later
// Where the object sits in the world, and the scene checks that need both the
// scene and the mesh.
#include "caustic/mesh.hpp"
#include "caustic/optics.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace caustic {

using optics::basis_around;

glm::dmat3 euler_xyz_degrees(const glm::dvec3& degrees) {
  const glm::dvec3 r = glm::radians(degrees);
  const double cx = std::cos(r.x), sx = std::sin(r.x);
  const double cy = std::cos(r.y), sy = std::sin(r.y);
  const double cz = std::cos(r.z), sz = std::sin(r.z);
  // glm is column-major: each dmat3 constructor argument group is a column.
  const glm::dmat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx);
  const glm::dmat3 ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
  const glm::dmat3 rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
  return rx * ry * rz;
}

MeshBounds mesh_bounds(const Mesh& mesh, const glm::dvec3& flat_normal) {
  const auto [e1, e2] = basis_around(flat_normal);
  MeshBounds b{flat_normal, glm::dvec3(std::numeric_limits<double>::infinity()),
               glm::dvec3(-std::numeric_limits<double>::infinity())};
  for (const glm::dvec3 p : mesh.positions) {
    const glm::dvec3 q(glm::dot(p, e1), glm::dot(p, e2), glm::dot(p, flat_normal));
    b.lo = glm::min(b.lo, q);
    b.hi = glm::max(b.hi, q);
  }
  return b;
}

Placement place_object(const ObjectParams& object, const Mesh& mesh) {
  return place_object(object, mesh_bounds(mesh, object.flat_face_normal));
}

Placement place_object(const ObjectParams& object, const MeshBounds& bounds) {
  if (bounds.normal != object.flat_face_normal)
    throw std::invalid_argument("mesh bounds taken about another flat-face normal");
  const glm::dvec3 n = object.flat_face_normal;
  const auto [e1, e2] = basis_around(n);
  const glm::dvec3 lo = bounds.lo, hi = bounds.hi;
  // A solid or a surface has no flat face: the plane through its extreme
  // vertex only frames the footprint and the public box.
  const double offset_mesh = object.shape != Shape::slab ? hi.z : object.flat_face_offset.value_or(hi.z);
  const glm::dvec3 mid = 0.5 * (lo + hi);
  const glm::dvec3 centre_mesh = mid.x * e1 + mid.y * e2 + mid.z * n;

  Placement out;
  out.rotation = euler_xyz_degrees(object.rotation_deg);
  glm::dvec3 origin(0.0);  // mesh point that lands on object.position
  if (object.fit_size) {
    const double footprint = std::max(hi.x - lo.x, hi.y - lo.y);
    out.scale = footprint > 0 ? *object.fit_size / footprint : 1.0;
    // The centre of the public box (the footprint, from the lowest vertex
    // to the flat face), not of the vertices: the face's highest point
    // below a flat face is hidden, and a centre halfway to it moved all
    // that fit_size places (the flat face, the followed screen) by half of it.
    origin = mid.x * e1 + mid.y * e2 + 0.5 * (lo.z + std::max(offset_mesh, hi.z)) * n;
  }
  glm::dmat4 m(out.rotation * out.scale);
  m[3] = glm::dvec4(object.position - out.rotation * (out.scale * origin), 1.0);
  out.model = m;

  out.flat_normal = glm::normalize(out.rotation * n);
  const glm::dvec3 plane_point = glm::dvec3(m * glm::dvec4(offset_mesh * n, 1.0));
  out.flat_offset = glm::dot(plane_point, out.flat_normal);
  out.center = glm::dvec3(m * glm::dvec4(centre_mesh, 1.0));
  out.max_depth = (offset_mesh - lo.z) * out.scale;
  out.footprint = glm::dvec2(hi.x - lo.x, hi.y - lo.y) * out.scale;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner = ((i & 1) ? hi.x : lo.x) * e1 + ((i & 2) ? hi.y : lo.y) * e2 +
                              ((i & 4) ? std::max(offset_mesh, hi.z) : lo.z) * n;
    out.box[static_cast<std::size_t>(i)] = glm::dvec3(m * glm::dvec4(corner, 1.0));
  }
  return out;
}

namespace {

// Whether p lies in the object's (public) bounding box, a rectangular box
// whose corners 1, 2 and 4 lie along its edges from corner 0.
bool in_box(const Placement& placement, const glm::dvec3& p) {
  const auto& b = placement.box;
  for (const std::size_t i : {1u, 2u, 4u}) {
    const glm::dvec3 edge = b[i] - b[0];
    const double along = glm::dot(p - b[0], edge), length2 = glm::dot(edge, edge);
    if (!(along >= -1e-9 * length2 && along <= length2 * (1 + 1e-9))) return false;
  }
  return true;
}

// The light must stay outside the slab; the slab's depth is public. A solid
// has no flat face and no slab: beside it, level with it, the light is lit
// as any other; within its box it would start its rays inside the body, or
// with part of it behind (the launch refuses that too, caustic/launch.hpp,
// but a light at the box's centre has no direction to the object at all).
// A surface (water) is the face of a medium that fills the space beyond it,
// the screen included: each ray from the light refracts into it once. A
// light on the screen's side lies in that medium, where nothing refracts
// (the model would send its rays away from the screen: a black frame); one
// level with the surface's relief meets some of it from below. Refused, as a
// slab's light inside its glass is (docs/physics.md §14).
void check_surface_light(const Scene& scene, const Placement& placement) {
  const glm::dvec3 nf = placement.flat_normal;
  const double eps = 1e-6 * std::max(1.0, placement.max_depth);
  const auto height = [&](const glm::dvec3& p) { return glm::dot(p, nf) - placement.flat_offset; };
  const double light = height(scene.light.position), screen = height(scene.screen.center);
  if (light <= eps && light >= -placement.max_depth - eps)
    throw SceneError("light.position", "the point light lies level with the surface's relief, between the heights "
                                       "of its lowest and highest points: light it from one side (object.shape "
                                       "\"surface\")");
  const bool screen_above = screen > eps, screen_below = screen < -placement.max_depth - eps;
  if ((light > 0 && screen_above) || (light < 0 && screen_below))
    throw SceneError("light.position", "the point light lies on the screen's side of the surface, in the medium that "
                                       "fills the space beyond it (object.shape \"surface\"), where no ray crosses "
                                       "the surface: place it on the surface's other side");
}

void check_point_light(const Scene& scene, const Placement& placement) {
  const glm::dvec3 nf = placement.flat_normal;
  if (scene.light.type == LightType::point && scene.object.shape == Shape::solid) {
    if (in_box(placement, scene.light.position))
      throw SceneError("light.position", "the point light lies inside the object's bounding box");
    return;
  }
  if (scene.light.type == LightType::point && scene.object.shape == Shape::surface)
    return check_surface_light(scene, placement);
  if (scene.light.type == LightType::point && scene.object.material == Material::refractive) {
    const double h = glm::dot(scene.light.position, nf) - placement.flat_offset;
    const double eps = 1e-6 * std::max(1.0, placement.max_depth);
    if (std::abs(h) <= eps) throw SceneError("light.position", "the point light lies on the object's flat face");
    if (h < 0 && h > -placement.max_depth - eps)
      throw SceneError("light.position", "the point light lies inside the object's slab");
  }
}

// Light leaves the object before it meets a receiver: no receiver's plane
// may pass through the object's bounding box (the public one, so the answer
// says nothing of the hidden face).
void check_receivers(const Scene& scene, const Placement& placement) {
  for (std::size_t i = 0; i < scene.receivers.size(); ++i) {
    const auto& r = scene.receivers[i];
    if (const ReceiverMesh* body = r.body()) {  // boxes apart: its and the object's (axis-aligned; a near miss is refused too)
      glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
      for (const glm::dvec3& q : placement.box) lo = glm::min(lo, q), hi = glm::max(hi, q);
      const glm::dvec3 a = body->lower(), b = body->upper();
      const char* kind = r.lathe ? "lathe" : "mesh";
      if (glm::all(glm::lessThan(a, hi)) && glm::all(glm::lessThan(lo, b)))
        throw SceneError("receivers[" + std::to_string(i) + "]." + kind,
                         std::string("the ") + kind + " reaches into the object's bounding box");
      continue;
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const glm::dvec3& q : placement.box) {
      lo = std::min(lo, glm::dot(q - r.center, r.normal));
      hi = std::max(hi, glm::dot(q - r.center, r.normal));
    }
    if (lo < 0 && hi > 0)
      throw SceneError("receivers[" + std::to_string(i) + "].center",
                       "the receiver's plane crosses the object's bounding box");
  }
}

}  // namespace

void check_geometry(const Scene& scene, const Mesh& mesh, const Placement& placement) {
  const glm::dvec3 nf = placement.flat_normal;
  double screen_min = std::numeric_limits<double>::infinity(), screen_max = -screen_min;
  double above_flat = -std::numeric_limits<double>::infinity();
  for (const glm::dvec3 p : mesh.positions) {
    const glm::dvec3 w = glm::dvec3(placement.model * glm::dvec4(p, 1.0));
    // The solid spans from each caustic-face vertex to the flat face above it.
    const glm::dvec3 on_flat = onto_flat_face(placement, w);
    const bool to_flat = scene.object.material == Material::refractive && scene.object.shape == Shape::slab;
    for (const glm::dvec3& q : {w, to_flat ? on_flat : w}) {
      const double s = glm::dot(q - scene.screen.center, scene.screen.normal);
      screen_min = std::min(screen_min, s);
      screen_max = std::max(screen_max, s);
    }
    above_flat = std::max(above_flat, glm::dot(w, nf) - placement.flat_offset);
  }
  const double tolerance = 1e-6 * std::max(1.0, placement.max_depth);
  if (scene.object.material == Material::refractive && above_flat > tolerance)
    throw SceneError("object.flat_face_offset",
                     "the flat face cuts through the mesh (a vertex lies on its outer side); raise the offset");
  if (screen_min < 0 && screen_max > 0)
    throw SceneError("screen.center", "the screen plane crosses the object");
  check_receivers(scene, placement);
  check_point_light(scene, placement);
}

void check_geometry_public(const Scene& scene, const Placement& placement) {
  double screen_min = std::numeric_limits<double>::infinity(), screen_max = -screen_min;
  for (const glm::dvec3& q : placement.box) {
    const double s = glm::dot(q - scene.screen.center, scene.screen.normal);
    screen_min = std::min(screen_min, s);
    screen_max = std::max(screen_max, s);
  }
  if (screen_min < 0 && screen_max > 0)
    throw SceneError("screen.center", "the screen plane crosses the object's bounding box");
  check_receivers(scene, placement);
  check_point_light(scene, placement);
}

}  // namespace caustic
