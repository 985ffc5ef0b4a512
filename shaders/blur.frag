// SPDX-License-Identifier: LGPL-2.1-or-later
// One direction of a separable, normalised Gaussian blur. The weights come
// from the CPU: an exp() per tap per texel was most of the blur's cost on a
// software renderer.
const int kMaxRadius = 48;
uniform sampler2D uSource;
uniform ivec2 uStep;   // (1, 0) or (0, 1)
uniform int uRadius;   // taps on each side
uniform float uWeights[kMaxRadius + 1];  // tap k's weight at |k|, summing to 1 over all 2 uRadius + 1 taps
layout(location = 0) out vec4 outBlurred;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  // Clamped to the texel's own tile (glow_cuts.glsl), as to the image's edge.
  ivec4 tile = glowTile(p);
  ivec2 first = tile.xy, last = tile.zw - 1;
  vec3 sum = vec3(0.0);
  for (int k = -uRadius; k <= uRadius; ++k)
    sum += uWeights[abs(k)] * texelFetch(uSource, clamp(p + k * uStep, first, last), 0).rgb;
  outBlurred = vec4(sum, 1.0);
}
