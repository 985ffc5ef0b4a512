// SPDX-License-Identifier: LGPL-2.1-or-later
// One ray per caustic-face vertex: through the object (refraction at both
// faces, or one reflection) to the screen plane. Outputs the hit in screen
// coordinates and what the geometry shader needs for the triangle's flux.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aTint;  // transmittance per channel; (1, 1, 1) for clear glass

uniform mat4 uModel;
uniform mat3 uRotation;
uniform vec3 uFlatNormal;   // outward, world
uniform float uFlatOffset;  // flat face: dot(x, uFlatNormal) = uFlatOffset
uniform float uIor;
uniform bool uReflective;
uniform bool uFlatFirst;    // the flat face faces the light
uniform bool uImmersed;     // a surface (object.shape): the screen lies in the medium, no second face
uniform bool uPointLight;
uniform bool uExactPointModel;
uniform vec3 uLightDir;     // directional: propagation direction
uniform vec3 uLightPos;     // point light position
uniform bool uFresnel;
uniform vec3 uScreenCenter;
uniform vec3 uScreenNormal;
uniform vec3 uScreenRight;
uniform vec3 uScreenUp;
uniform float uReportPlaneDistance;
// The surfaces that catch the light (caustic/receivers.hpp): the screen
// first. Alone it is its whole plane; with receivers each is its rectangle.
const int kSurfaces = 8;
uniform int uSurfaceCount;
uniform vec3 uSurfaceCenter[kSurfaces];
uniform vec3 uSurfaceNormal[kSurfaces];
uniform vec3 uSurfaceRight[kSurfaces];
uniform vec3 uSurfaceUp[kSurfaces];
uniform vec2 uSurfaceHalf[kSurfaces];

out VertexData {
  vec2 screen;         // hit on its surface, (right, up) from the surface's centre, world units
  vec2 plane;          // hit on the virtual plane behind the screen ("report" mode)
  vec3 footprint;      // where this vertex's ray entered the object (world)
  float transmittance; // product of Fresnel transmittances along the ray
  float valid;         // 1: reached the screen; 0: TIR, missed or grazing
  vec3 tint;
  float share;         // of its triangle's flux the triangle carries (caustic_landed.vert)
  float surface;       // which surface the ray landed on; -1: none
} vout;

// The ray would meet the caustic face from the wrong side: from within the
// glass (which lies on the flat face's side of it) for light arriving from
// outside, or from without for light inside. It crossed the face elsewhere
// first, so the vertex lies in the face's own shadow (raymodel's twin).
bool wrongSide(vec3 ray, vec3 n, bool inside) {
  float side = dot(ray, n) * dot(uFlatNormal, n);
  return inside ? side > 0.0 : side < 0.0;
}

void main() {
  vec3 v = (uModel * vec4(aPosition, 1.0)).xyz;
  vec3 n = normalize(uRotation * aNormal);
  vec3 incident = uPointLight ? normalize(v - uLightPos) : uLightDir;
  vec3 origin = v;
  vec3 dir = -uScreenNormal;  // replaced below; keeps rejected rays finite
  vec3 footprint = v;
  float transmittance = 1.0;
  float tFace;
  bool ok = true;

  if (uReflective) {
    dir = reflect(incident, faceAgainst(n, incident));
  } else if (uFlatFirst) {
    if (uPointLight && uExactPointModel) {
      footprint = pointLightEntry(uLightPos, v, uFlatNormal, uFlatOffset, uIor);
      incident = normalize(footprint - uLightPos);
    }
    vec3 inside;
    refractFresnel(incident, faceAgainst(uFlatNormal, incident), 1.0, uIor, inside, tFace);
    if (uPointLight && uExactPointModel) inside = normalize(v - footprint);
    else footprint = v + inside * ((uFlatOffset - dot(v, uFlatNormal)) / dot(inside, uFlatNormal));
    transmittance *= tFace;
    ok = !wrongSide(inside, n, true) && refractFresnel(inside, faceAgainst(n, inside), uIor, 1.0, dir, tFace);
    transmittance *= tFace;
  } else {
    vec3 inside;
    ok = refractFresnel(incident, faceAgainst(n, incident), 1.0, uIor, inside, tFace);
    ok = ok && (uImmersed || !wrongSide(incident, n, false));
    transmittance *= tFace;
    dir = inside;
    if (!uImmersed) {  // a slab's light leaves by the flat face; a surface's stays in
      float toward = dot(inside, uFlatNormal);
      ok = ok && toward > 1e-6;
      origin = v + inside * ((uFlatOffset - dot(v, uFlatNormal)) / max(toward, 1e-6));
      ok = ok && refractFresnel(inside, faceAgainst(uFlatNormal, inside), uIor, 1.0, dir, tFace);
      transmittance *= tFace;
    }
  }

  // The first surface ahead of the ray.
  int landed = -1;
  float nearest = 1e30;
  vec2 local = vec2(0.0);
  for (int i = 0; i < uSurfaceCount; ++i) {
    float d = dot(dir, uSurfaceNormal[i]);
    float t = dot(uSurfaceCenter[i] - origin, uSurfaceNormal[i]) / d;
    if (!(abs(d) > 1e-6 && t > 0.0 && t < nearest) || isinf(t) || isnan(t)) continue;
    vec3 p = origin + t * dir - uSurfaceCenter[i];
    vec2 at = vec2(dot(p, uSurfaceRight[i]), dot(p, uSurfaceUp[i]));
    if (uSurfaceCount > 1 && any(greaterThan(abs(at), uSurfaceHalf[i]))) continue;
    landed = i;
    nearest = t;
    local = at;
  }
  // Alone, a screen the ray misses drops its triangles; among receivers the
  // corners that landed keep their shares (caustic.geom).
  ok = ok && (landed >= 0 || uSurfaceCount > 1);
  float denom = dot(dir, uScreenNormal);
  vec3 planeCenter = uScreenCenter - uReportPlaneDistance * uScreenNormal;
  vec3 planeHit = origin + (dot(planeCenter - origin, uScreenNormal) / denom) * dir;

  vout.screen = local;
  vout.surface = float(landed);
  vout.plane = vec2(dot(planeHit - planeCenter, uScreenRight), dot(planeHit - planeCenter, uScreenUp));
  vout.footprint = footprint;
  vout.transmittance = uFresnel ? transmittance : 1.0;
  vout.valid = ok ? 1.0 : 0.0;
  vout.tint = aTint;
  vout.share = 1.0;
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
