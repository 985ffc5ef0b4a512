// SPDX-License-Identifier: LGPL-2.1-or-later
// Adds an image of irradiance the CPU already deposited (src/engine/
// coverage.hpp) into the caustic target, times the pass's colour: the
// blending sums it with the other passes as caustic.frag's output would.
uniform sampler2D uCoverage;  // the target's size: one texel a pixel
uniform bool uGrey;           // one channel, for a monochrome target
uniform vec3 uWeight;         // as caustic.frag's
layout(location = 0) out vec4 outIrradiance;

void main() {
  vec3 texel = texelFetch(uCoverage, ivec2(gl_FragCoord.xy), 0).rgb;
  outIrradiance = vec4(uWeight * (uGrey ? vec3(texel.r) : texel), 0.0);
}
