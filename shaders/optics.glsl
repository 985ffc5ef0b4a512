// SPDX-License-Identifier: LGPL-2.1-or-later
// GLSL twin of src/optics/include/caustic/optics.hpp (same conventions):
// directions point the way light travels; eta = n_from / n_to; the normal
// handed to refraction faces against the incident ray.

// n or -n, whichever faces against the incident direction i.
vec3 faceAgainst(vec3 n, vec3 i) { return dot(n, i) < 0.0 ? n : -n; }

// Snell refraction. Returns false on total internal reflection; otherwise
// writes the transmitted direction and the Fresnel power transmittance
// (unpolarised) for light from index n1 into n2. Equal indices are no
// interface: the ray goes on whole (the formulas are 0 / 0 at grazing
// incidence and, within float rounding of it, reflect everything).
bool refractFresnel(vec3 i, vec3 n, float n1, float n2, out vec3 t, out float transmittance) {
  if (n1 == n2) {
    t = i;
    transmittance = 1.0;
    return true;
  }
  float eta = n1 / n2;
  float cosI = -dot(n, i);
  float k = 1.0 - eta * eta * (1.0 - cosI * cosI);
  if (k < 0.0) {
    t = vec3(0.0);
    transmittance = 0.0;
    return false;
  }
  float cosT = sqrt(k);
  t = normalize(eta * i + (eta * cosI - cosT) * n);
  float rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
  float rp = (n1 * cosT - n2 * cosI) / (n1 * cosT + n2 * cosI);
  transmittance = 1.0 - 0.5 * (rs * rs + rp * rp);
  return true;
}

// Entry point on the flat interface dot(x, planeN) = planeD of the ray from a
// point light to v inside glass of index n (light in front, v behind the
// plane): bisection on sin(theta_i) - n sin(theta_t) in the plane of incidence.
vec3 pointLightEntry(vec3 light, vec3 v, vec3 planeN, float planeD, float n) {
  float hL = dot(light, planeN) - planeD;
  float hV = planeD - dot(v, planeN);
  vec3 footL = light - hL * planeN;
  vec3 across = (v + hV * planeN) - footL;
  float d = length(across);
  if (d <= 1e-7 * (hL + hV)) return footL;
  float lo = 0.0, hi = d;
  for (int iter = 0; iter < 32; ++iter) {
    float x = 0.5 * (lo + hi);
    float f = x * inversesqrt(x * x + hL * hL) - n * (d - x) * inversesqrt((d - x) * (d - x) + hV * hV);
    if (f < 0.0) lo = x; else hi = x;
  }
  return footL + (0.5 * (lo + hi) / d) * across;
}

// Solid angle of triangle (a, b, c) seen from eye (Van Oosterom & Strackee).
float solidAngle(vec3 eye, vec3 a, vec3 b, vec3 c) {
  vec3 ra = a - eye, rb = b - eye, rc = c - eye;
  float la = length(ra), lb = length(rb), lc = length(rc);
  float triple = dot(ra, cross(rb - ra, rc - ra));
  float denom = la * lb * lc + dot(ra, rb) * lc + dot(ra, rc) * lb + dot(rb, rc) * la;
  return abs(2.0 * atan(triple, denom));
}
