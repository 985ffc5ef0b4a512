// SPDX-License-Identifier: LGPL-2.1-or-later
// The per-vertex ray method of the engine (docs/physics.md ch. 4-5) in
// double precision on the CPU: the twin of shaders/caustic.vert and
// caustic.geom. Tests hold the GPU renders against it (flux bookkeeping,
// validity of each ray), and it lets tools reason about a frame without a
// GL context. It is not the reference: that is the independent photon tracer.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/receivers.hpp"  // screen_right

namespace caustic {

/// One caustic-face vertex's ray through the object to the screen.
struct VertexRay {
  bool valid = false;         ///< false: TIR, grazing, or the screen lies behind the ray
  glm::dvec2 screen{0.0};     ///< hit on the screen, (right, up) from its centre
  glm::dvec3 footprint{0.0};  ///< where the ray entered the object
  double transmittance = 1.0; ///< Fresnel product along the ray (1 when Fresnel is off)
};


/// The ray leaving the object from one caustic-face vertex, before it meets
/// any surface: what the screen and the receivers are intersected with.
struct ExitRay {
  bool valid = false;          ///< false: TIR or grazing inside the object
  glm::dvec3 origin{0.0};      ///< where it leaves the object (world)
  glm::dvec3 direction{0.0};   ///< unit, world
  glm::dvec3 footprint{0.0};   ///< where it entered the object
  double transmittance = 1.0;  ///< Fresnel product (1 when Fresnel is off)
  bool shaded = false;         ///< not valid: the light would meet the face from the wrong side
};

/// Whether light meets the flat face before the caustic face.
bool flat_face_first(const Scene& scene, const Placement& placement);

/// Follows the ray through caustic-face vertex `v` (world) with normal `n`
/// (world, unit) out of the object refracted with index `ior` (one
/// wavelength's, or object.ior).
ExitRay exit_ray(const Scene& scene, const Placement& placement, double ior, const glm::dvec3& v, const glm::dvec3& n);

/// The share (0 to 1) of `mesh`'s vertices, placed by `placement`, that lie
/// in the caustic face's own shadow under the scene's light (ExitRay::shaded):
/// they carry no light, and the ridges in front of them shade more of the
/// face than the per-vertex method sees (docs/physics.md §6), so its picture
/// then holds more light than enters. 0 for mirrors, solids and water
/// surfaces, which the rule does not cover. It reads the real mesh: for the
/// operator's tools, never for an answer to a visitor.
double self_shaded_share(const Scene& scene, const Placement& placement, const Mesh& mesh);

/// Traces the ray through caustic-face vertex `v` (world) with normal `n` (world, unit).
VertexRay trace_vertex(const Scene& scene, const Placement& placement, const glm::dvec3& v, const glm::dvec3& n);

/// A point light's relative irradiance is normalised to what it delivers at
/// the object's centre (docs/physics.md ch. 1): the square of that distance.
double reference_distance2(const Scene& scene, const Placement& placement);

/// Flux (relative units: per unit E0, times area in world units) that enters
/// the triangle whose vertex rays are a, b, c, including the mean Fresnel
/// transmittance: what the engine spreads over the projected triangle.
double triangle_flux(const Scene& scene, const Placement& placement, const VertexRay& a, const VertexRay& b,
                     const VertexRay& c);

/// Total flux that reaches the screen plane by the per-vertex method: the
/// sum of triangle_flux over triangles whose three rays are valid.
struct FluxSummary {
  double flux = 0.0;
  std::size_t valid_triangles = 0;
  glm::dvec2 screen_min{0.0}, screen_max{0.0};  ///< bounds of the valid hits
};
FluxSummary summarize_flux(const Scene& scene, const Mesh& mesh, const Placement& placement);

}  // namespace caustic
