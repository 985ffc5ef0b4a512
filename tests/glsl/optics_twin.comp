// SPDX-License-Identifier: LGPL-2.1-or-later
// Evaluates shaders/optics.glsl on a batch of cases for glsl_twin_test.
layout(local_size_x = 64) in;

struct Case {
  vec4 incident;  // xyz: incident direction
  vec4 normal;    // xyz: surface normal, either orientation
  vec4 indices;   // x: n_from, y: n_to, z: glass index for the point-light entry
  vec4 light, vertex, triA, triB, triC;
  vec4 refracted; // out: xyz transmitted direction
  vec4 results;   // out: x 1 if transmitted, y transmittance, z solid angle
  vec4 entry;     // out: xyz point-light entry on the plane z = 0
  vec4 pad;
};
layout(std430, binding = 1) buffer Cases { Case cases[]; };

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= uint(cases.length())) return;
  Case c = cases[k];
  vec3 t;
  float transmittance;
  vec3 n = faceAgainst(c.normal.xyz, c.incident.xyz);
  bool ok = refractFresnel(c.incident.xyz, n, c.indices.x, c.indices.y, t, transmittance);
  cases[k].refracted = vec4(t, 0.0);
  cases[k].results = vec4(ok ? 1.0 : 0.0, transmittance, solidAngle(c.light.xyz, c.triA.xyz, c.triB.xyz, c.triC.xyz), 0.0);
  cases[k].entry = vec4(pointLightEntry(c.light.xyz, c.vertex.xyz, vec3(0.0, 0.0, 1.0), 0.0, c.indices.z), 0.0);
}
