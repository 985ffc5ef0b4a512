// Bright pass at half resolution: what lies above the bloom threshold,
// averaged over the 2x2 full-resolution texels under each output texel.
uniform sampler2D uHdr;
uniform float uThreshold;
layout(location = 0) out float outBright;

void main() {
  ivec2 base = 2 * ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uHdr, 0) - 1;
  float sum = 0.0;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx)
      sum += max(texelFetch(uHdr, min(base + ivec2(dx, dy), last), 0).r - uThreshold, 0.0);
  outBright = 0.25 * sum;
}
