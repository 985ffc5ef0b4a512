// SPDX-License-Identifier: LGPL-2.1-or-later
// A drop on the pool (docs/physics.md §14), the twin of WaveSolver::drop:
// -s (1 - q) exp(-q), q = |x - x0|^2 / (2 sigma^2), added to both steps (a
// drop starts at rest) within its reach, less uMean everywhere (what the
// walls cut off the rim, so the volume is kept).
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) buffer Before { float before[]; };
layout(std430, binding = 1) buffer Now { float now[]; };
uniform int uGrid;
uniform float uHalf, uSpacing;
uniform vec2 uCentre;       // metres
uniform float uStrength, uRadius;
uniform ivec4 uReach;       // first i, first j, last i, last j
uniform float uMean;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uGrid || p.y >= uGrid) return;
  float h = -uMean;
  if (all(greaterThanEqual(p, uReach.xy)) && all(lessThanEqual(p, uReach.zw))) {
    vec2 d = vec2(-uHalf) + vec2(p) * uSpacing - uCentre;
    float q = dot(d, d) / (2.0 * uRadius * uRadius);
    h += -uStrength * (1.0 - q) * exp(-q);
  }
  int k = p.y * uGrid + p.x;
  now[k] += h;
  before[k] += h;
}
