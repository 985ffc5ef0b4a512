// SPDX-License-Identifier: LGPL-2.1-or-later
// Local tone mapping (after Durand and Dorsey 2002): a pixel's value is
// divided by a power of its neighbourhood's brightness, the "base": log2 of
// the lit pixels, averaged over 8x8 blocks and smoothed by an edge-stopping
// (bilateral) filter so that a bright focus does not darken its dark
// surroundings in a halo. Large-scale contrast is compressed by
// uLocalStrength (0: none, 1: flattened), detail within ~40 pixels is kept.
// A base of 0 (the light's own irradiance) is left alone, so manual exposure
// means the same with either operator for an evenly lit screen.
uniform sampler2D uBase;       // R16F, log2 brightness, 1/8 of the HDR size
uniform float uLocalStrength;  // 0 for the global operator

// Relative luminance of linear sRGB (Rec. 709): what metering and the local
// operator judge brightness by; a grey (r, r, r) gives r.
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

float local_factor(vec2 uv) {
  return uLocalStrength > 0.0 ? exp2(-uLocalStrength * texture(uBase, uv).r) : 1.0;
}
