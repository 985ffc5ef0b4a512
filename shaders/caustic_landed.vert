// SPDX-License-Identifier: LGPL-2.1-or-later
// The multipass method's rays arrive already traced (caustic/light_grid.hpp,
// on the CPU through every face of a solid): this stage only hands them to
// caustic.geom in the per-vertex method's form, so both share one deposit.
layout(location = 0) in vec2 aScreen;
layout(location = 1) in vec2 aPlane;
layout(location = 2) in vec3 aFootprint;
layout(location = 3) in float aTransmittance;
layout(location = 4) in float aValid;
layout(location = 5) in vec3 aTint;
layout(location = 6) in float aShare;
layout(location = 7) in float aSurface;

out VertexData {
  vec2 screen;
  vec2 plane;
  vec3 footprint;
  float transmittance;
  float valid;
  vec3 tint;
  float share;
  float surface;
} vout;

void main() {
  vout.screen = aScreen;
  vout.plane = aPlane;
  vout.footprint = aFootprint;
  vout.transmittance = aTransmittance;
  vout.valid = aValid;
  vout.tint = aTint;
  vout.share = aShare;
  vout.surface = aSurface;
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
