// SPDX-License-Identifier: LGPL-2.1-or-later
// A triangle the CPU already set up (src/engine/splats.hpp, the twin of
// caustic.geom), one square of its bounding box at a time: a GL point over
// the square's pixels, carrying what caustic.frag reads. A point is one
// primitive where a quad is two, and a software rasteriser sets up
// primitives one at a time.
layout(location = 0) in vec4 aAB;     // corners a, b in window pixels
layout(location = 1) in vec4 aCLo;    // corner c; the square's lowest pixel corner
layout(location = 2) in vec3 aSplat;  // the square's side in pixels; irradiance; 1 for a point
layout(location = 3) in vec3 aTint;

uniform vec2 uViewport;  // pixels: the target's and a margin past its far edges (RayPass::draw_splats)

flat out float gIrradiance;
flat out vec2 gA;
flat out vec2 gB;
flat out vec2 gC;
flat out float gPoint;
flat out vec3 gTint;

void main() {
  gA = aAB.xy;
  gB = aAB.zw;
  gC = aCLo.xy;
  gIrradiance = aSplat.y;
  gPoint = aSplat.z;
  gTint = aTint;
  // A point of side s covers the pixels whose centres lie within s/2 of
  // its centre: exactly the s x s pixels from the corner.
  gl_PointSize = aSplat.x;
  gl_Position = vec4((aCLo.zw + 0.5 * aSplat.x) / uViewport * 2.0 - 1.0, 0.0, 1.0);
}
