// SPDX-License-Identifier: LGPL-2.1-or-later
// Local tone mapping, step 1: each output texel covers 8x8 HDR texels and
// holds the mean log2 of its lit ones (r) and the fraction lit (g); unlit
// blocks are skipped by the bilateral step.
uniform sampler2D uHdr;
uniform float uLog2Lit;
layout(location = 0) out vec2 outBase;

void main() {
  ivec2 base = 8 * ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uHdr, 0) - 1;
  float sum = 0.0, lit = 0.0;
  for (int dy = 0; dy < 8; ++dy)
    for (int dx = 0; dx < 8; ++dx) {
      float h = luminance(texelFetch(uHdr, min(base + ivec2(dx, dy), last), 0).rgb);
      if (h > exp2(uLog2Lit)) {
        sum += log2(h);
        lit += 1.0;
      }
    }
  outBase = lit > 0.0 ? vec2(sum / lit, lit / 64.0) : vec2(0.0);
}
