// SPDX-License-Identifier: LGPL-2.1-or-later
// A mesh in Embree 3 (a slab's caustic face, or a closed solid): one device
// and one committed scene, intersected with interpolated vertex normals.
// The photon reference and the multipass tracer both intersect through it.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/optics.hpp"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>

namespace caustic {

using optics::Vec3;

// Owns an Embree device and a committed scene of the mesh (world space).
class Geometry {
 public:
  Geometry(const Mesh& mesh, const Placement& placement) : mesh_(mesh), placement_(placement) {
    device_ = rtcNewDevice("threads=1");
    if (!device_) throw std::runtime_error("cannot create an Embree device");
    scene_ = rtcNewScene(device_);
    // Watertight: a ray through a shared edge or vertex must not slip between triangles.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.positions.size()));
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3 w = world(i);
      v[3 * i] = static_cast<float>(w.x);
      v[3 * i + 1] = static_cast<float>(w.y);
      v[3 * i + 2] = static_cast<float>(w.z);
    }
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) t[3 * i + k] = mesh.triangles[i][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
  }
  ~Geometry() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;

  Vec3 world(std::size_t i) const {
    return Vec3(placement_.model * glm::dvec4(Vec3(mesh_.positions[i]), 1.0));
  }

  struct Hit {
    Vec3 point, normal;  // normal interpolated from the vertices, unit, world
    Vec3 tint{1.0};      // the face's transmittance there, interpolated (1: clear)
    Vec3 facet{0.0};     // the triangle's own normal by its winding, unit, world
    unsigned triangle = 0;
  };

  // First intersection of the ray with the mesh, beyond `t_min`.
  bool intersect(const Vec3& origin, const Vec3& dir, double t_min, Hit* hit) const {
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(origin.x);
    rh.ray.org_y = static_cast<float>(origin.y);
    rh.ray.org_z = static_cast<float>(origin.z);
    rh.ray.dir_x = static_cast<float>(dir.x);
    rh.ray.dir_y = static_cast<float>(dir.y);
    rh.ray.dir_z = static_cast<float>(dir.z);
    rh.ray.tnear = static_cast<float>(t_min);
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const auto& tri = mesh_.triangles[rh.hit.primID];
    const double u = rh.hit.u, w = rh.hit.v;
    const Vec3 n = (1 - u - w) * Vec3(mesh_.normals[tri.x]) + u * Vec3(mesh_.normals[tri.y]) +
                   w * Vec3(mesh_.normals[tri.z]);
    hit->point = origin + static_cast<double>(rh.ray.tfar) * dir;
    hit->normal = glm::normalize(placement_.rotation * n);
    hit->tint = Vec3(1.0);
    hit->triangle = rh.hit.primID;
    // From the mesh, not Embree's Ng: the winding decides outward here.
    const Vec3 p0(mesh_.positions[tri.x]), p1(mesh_.positions[tri.y]), p2(mesh_.positions[tri.z]);
    const Vec3 facet = placement_.rotation * glm::cross(p1 - p0, p2 - p0);
    hit->facet = glm::length(facet) > 0 ? glm::normalize(facet) : hit->normal;
    if (tinted(mesh_))
      hit->tint = (1 - u - w) * Vec3(mesh_.colours[tri.x]) + u * Vec3(mesh_.colours[tri.y]) +
                  w * Vec3(mesh_.colours[tri.z]);
    return true;
  }

 private:
  const Mesh& mesh_;
  const Placement& placement_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace caustic
