// SPDX-License-Identifier: LGPL-2.1-or-later
// Geometric-optics primitives shared by the CPU side of the appliance: the
// reference tracer, tests and scene validation. The GLSL twins live in
// shaders/optics.glsl; tests hold both against docs/physics.md.
//
// Conventions (the same as GLSL's reflect/refract):
//  - directions point the way light travels; `i` is the incident direction;
//  - `eta` is n_from / n_to: entering glass from air eta = 1/n, leaving it eta = n;
//  - the normal passed to refract() faces against the incident ray
//    (dot(n, i) < 0); use face_against() to orient a surface normal first.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <optional>
#include <utility>

namespace caustic::optics {

using Vec3 = glm::dvec3;

/// Mirror reflection of `i` about the plane with unit normal `n` (either side).
inline Vec3 reflect(const Vec3& i, const Vec3& n) { return i - 2.0 * glm::dot(n, i) * n; }

/// `n` or `-n`, whichever faces against the incident direction `i`.
/// A normal exactly perpendicular to `i` (grazing incidence), or a NaN
/// product, is returned negated.
inline Vec3 face_against(const Vec3& n, const Vec3& i) { return glm::dot(n, i) < 0.0 ? n : -n; }

/// A transmitted ray and the cosines Snell's law relates.
struct Refraction {
  Vec3 direction;  ///< unit transmitted direction
  double cos_i;    ///< |cos| of the angle of incidence
  double cos_t;    ///< cos of the angle of transmission (sqrt(k) of optics ch. 2)
};

/// Snell refraction of unit `i` at unit normal `n` (facing against `i`),
/// eta = n_from / n_to. Total internal reflection (k < 0) returns no ray;
/// exactly at the critical angle (k = 0) the ray runs along the surface
/// (cos_t = 0). At grazing incidence (cos_i = 0) into a denser medium the ray
/// bends to the critical angle. NaN in `i`, `n` or `eta` gives a NaN
/// direction rather than no ray, as the GLSL twin does: scenes are validated
/// finite before they get here.
inline std::optional<Refraction> refract(const Vec3& i, const Vec3& n, double eta) {
  const double cos_i = -glm::dot(n, i);
  const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
  if (k < 0.0) return std::nullopt;
  const double cos_t = std::sqrt(k);
  return Refraction{eta * i + (eta * cos_i - cos_t) * n, cos_i, cos_t};
}

/// Amplitude and power reflection coefficients of one interface.
struct FresnelTerms {
  double r_s;          ///< perpendicular (s) amplitude coefficient
  double r_p;          ///< parallel (p) amplitude coefficient
  double reflectance;  ///< unpolarised power reflectance (r_s^2 + r_p^2) / 2
};

/// Fresnel equations for light going from index n1 to n2, given the cosines of
/// the incident and transmitted angles (both non-negative). The caller detects
/// TIR before calling (there is no cos_t then); fresnel_transmittance() does both.
/// Grazing incidence (cos_i = 0) and the critical angle (cos_t = 0) reflect
/// everything (R = 1). Equal indices are no interface (R = 0 at every angle):
/// said first, since at grazing incidence the formulas are 0 / 0 there and,
/// within float rounding of it (cos_i² below 1e-16), wrongly give R = 1.
inline FresnelTerms fresnel(double cos_i, double cos_t, double n1, double n2) {
  if (n1 == n2) return {0.0, 0.0, 0.0};
  const double r_s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double r_p = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
  return {r_s, r_p, 0.5 * (r_s * r_s + r_p * r_p)};
}

/// Unpolarised power transmittance T = 1 - R for a ray with |cos| of
/// incidence `cos_i` crossing from index n1 to n2. TIR and grazing incidence
/// give 0, equal indices 1, a NaN input NaN.
inline double fresnel_transmittance(double cos_i, double n1, double n2) {
  const double eta = n1 / n2;
  const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
  if (k < 0.0) return 0.0;
  return 1.0 - fresnel(cos_i, std::sqrt(k), n1, n2).reflectance;
}

/// Critical angle (radians) for light leaving index n into index 1: pi / 2
/// at n = 1, NaN below (no total internal reflection there).
inline double critical_angle(double n) { return std::asin(1.0 / n); }

/// Brewster's angle (radians) for light from n1 into n2, where r_p vanishes.
inline double brewster_angle(double n1, double n2) { return std::atan(n2 / n1); }

/// Two unit vectors (e1, e2) completing unit `n` to a right-handed
/// orthonormal basis (e1 x e2 = n).
inline std::pair<Vec3, Vec3> basis_around(const Vec3& n) {
  const Vec3 helper = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 e1 = glm::normalize(glm::cross(helper, n));
  return {e1, glm::cross(n, e1)};
}

/// A plane dot(x, normal) = offset with unit normal.
struct Plane {
  Vec3 normal;
  double offset;
  double signed_distance(const Vec3& x) const { return glm::dot(x, normal) - offset; }
};

/// Exact entry point of the ray from a point light `light` to a point `v`
/// inside a medium of index `n` bounded by the flat interface `plane`
/// (light on the positive side, v on the negative side). Solves Snell's law in
/// the plane of incidence by safeguarded bisection (docs/physics.md ch. 4):
/// sin(theta_i) = n sin(theta_t) for the entry point at horizontal distance x.
/// Returns no point when the light is not strictly in front of the plane or
/// `v` not strictly behind it (a NaN height included). Converges to 1e-15 of
/// the feet's distance (80 halvings at most); straight below the light it is
/// the light's foot.
std::optional<Vec3> point_light_entry(const Vec3& light, const Vec3& v, const Plane& plane, double n);

/// Solid angle (steradians) that the triangle (a, b, c) subtends at `eye`
/// (Van Oosterom & Strackee 1983), always non-negative. A triangle of no
/// area, or one whose plane holds the eye outside it, subtends 0; an eye in
/// its plane and inside it, 2 pi (the limit from either side).
double solid_angle(const Vec3& eye, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace caustic::optics
