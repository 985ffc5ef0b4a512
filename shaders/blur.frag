// SPDX-License-Identifier: LGPL-2.1-or-later
// One direction of a separable, normalised Gaussian blur.
uniform sampler2D uSource;
uniform ivec2 uStep;   // (1, 0) or (0, 1)
uniform float uSigma;  // texels
uniform int uRadius;   // taps on each side
layout(location = 0) out vec4 outBlurred;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(uSource, 0) - 1;
  vec3 sum = vec3(0.0);
  float weights = 0.0;
  for (int k = -uRadius; k <= uRadius; ++k) {
    float w = exp(-0.5 * float(k * k) / (uSigma * uSigma));
    sum += w * texelFetch(uSource, clamp(p + k * uStep, ivec2(0), last), 0).rgb;
    weights += w;
  }
  outBlurred = vec4(sum / weights, 1.0);
}
