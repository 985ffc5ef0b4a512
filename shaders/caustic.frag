// SPDX-License-Identifier: LGPL-2.1-or-later
// Adds E times the exact fraction of this pixel that the triangle covers;
// additive blending then sums overlapping (folded) sheets, as light does.
flat in float gIrradiance;
flat in vec2 gA;
flat in vec2 gB;
flat in vec2 gC;
flat in float gPoint;
flat in vec3 gTint;  // the face's colour filter over this triangle
// The pass's colour: (1, 1, 1) for a monochrome frame, a wavelength band's
// white-balanced RGB for a spectral one (passes add up in an RGBA target).
uniform vec3 uWeight;
layout(location = 0) out vec4 outIrradiance;

// Mean of clamp(t, 0, 1) for t running linearly from u0 to u1, written so
// that every term scales with |u1 - u0|: no cancellation for steep edges.
float meanRamp(float u0, float u1) {
  float lo = min(u0, u1), hi = max(u0, u1);
  if (hi - lo < 1e-7) return clamp(0.5 * (lo + hi), 0.0, 1.0);
  float cl = clamp(lo, 0.0, 1.0), ch = clamp(hi, 0.0, 1.0);
  return (0.5 * (ch - cl) * (ch + cl) + (max(hi, 1.0) - max(lo, 1.0))) / (hi - lo);
}

// Signed contribution of the edge p -> q to the area of the polygon inside
// the unit cell [0,1]^2: the integral over the edge's part within 0 <= y <= 1
// of the cell's width to the right of the edge, clamp(1 - x, 0, 1) dy.
// Summed over a closed polygon this is minus its covered area when the
// polygon winds counter-clockwise (plus when clockwise). No loops, no
// arrays: a software rasteriser runs it as straight-line SIMD code.
float edgeCoverage(vec2 p, vec2 q) {
  float dy = q.y - p.y;
  if (abs(dy) < 1e-12) return 0.0;
  float y0 = clamp(p.y, 0.0, 1.0), y1 = clamp(q.y, 0.0, 1.0);
  float slope = (q.x - p.x) / dy;
  float u0 = 1.0 - (p.x + (y0 - p.y) * slope);  // width to the right at y0
  float u1 = 1.0 - (p.x + (y1 - p.y) * slope);
  return meanRamp(u0, u1) * (y1 - y0);
}

void main() {
  if (gPoint > 0.5) {
    outIrradiance = vec4(uWeight * gTint * gIrradiance, 0.0);
    return;
  }
  vec2 cell = floor(gl_FragCoord.xy);
  vec2 a = gA - cell, b = gB - cell, c = gC - cell;
  float covered = abs(edgeCoverage(a, b) + edgeCoverage(b, c) + edgeCoverage(c, a));
  outIrradiance = vec4(uWeight * gTint * (gIrradiance * min(covered, 1.0)), 0.0);
}
