// SPDX-License-Identifier: LGPL-2.1-or-later
// Local tone mapping, step 2: a bilateral filter of the block log-means.
// Neighbours more than ~1.5 stops away from the centre weigh little, so the
// base follows the edge of a bright focus instead of blurring across it.
// Unlit blocks take the spatial average of their lit neighbours, which keeps
// the upsampled base smooth at the rim of the light.
uniform sampler2D uBlocks;
layout(location = 0) out float outBase;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uBlocks, 0) - 1;
  vec2 centre = texelFetch(uBlocks, p, 0).rg;
  const float sigma_s = 2.5, sigma_r = 1.5;
  float sum = 0.0, weights = 0.0;
  for (int dy = -5; dy <= 5; ++dy)
    for (int dx = -5; dx <= 5; ++dx) {
      vec2 n = texelFetch(uBlocks, clamp(p + ivec2(dx, dy), ivec2(0), last), 0).rg;
      if (n.g <= 0.0) continue;
      float w = exp(-0.5 * float(dx * dx + dy * dy) / (sigma_s * sigma_s)) * n.g;
      if (centre.g > 0.0) w *= exp(-0.5 * (n.r - centre.r) * (n.r - centre.r) / (sigma_r * sigma_r));
      sum += w * n.r;
      weights += w;
    }
  outBase = weights > 0.0 ? sum / weights : 0.0;
}
