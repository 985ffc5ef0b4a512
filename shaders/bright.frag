// SPDX-License-Identifier: LGPL-2.1-or-later
// Bright pass at 1/uShrink of the resolution per side: what lies above the
// bloom threshold, averaged over the uShrink x uShrink full-resolution
// texels under each output texel (the excess is thresholded per texel, so
// the glow's flux does not depend on the shrink).
uniform sampler2D uHdr;
uniform float uThreshold;
uniform int uShrink;
layout(location = 0) out vec4 outBright;

void main() {
  ivec2 base = uShrink * ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uHdr, 0) - 1;
  vec3 sum = vec3(0.0);
  for (int dy = 0; dy < uShrink; ++dy)
    for (int dx = 0; dx < uShrink; ++dx)
      sum += max(texelFetch(uHdr, min(base + ivec2(dx, dy), last), 0).rgb - uThreshold, 0.0);
  outBright = vec4(sum / float(uShrink * uShrink), 1.0);
}
