// SPDX-License-Identifier: LGPL-2.1-or-later
// HDR relative irradiance plus bloom -> local compression (when on) ->
// exposure -> gamma -> 8-bit grey. A preview's HDR image is smaller than the
// output: it is upsampled here (bilinear); a full frame reads its texel
// exactly.
uniform sampler2D uHdr;
uniform vec2 uOutputSize;
uniform sampler2D uBloom;
uniform float uBloomStrength;
uniform float uExposure;
uniform float uGamma;
layout(location = 0) out vec4 outColor;

void main() {
  vec2 uv = gl_FragCoord.xy / uOutputSize;
  float hdr = textureSize(uHdr, 0) == ivec2(uOutputSize) ? texelFetch(uHdr, ivec2(gl_FragCoord.xy), 0).r
                                                         : texture(uHdr, uv).r;
  float bloom = uBloomStrength > 0.0 ? texture(uBloom, uv).r : 0.0;
  float value = max(hdr + uBloomStrength * bloom, 0.0) * local_factor(uv);
  float mapped = 1.0 - exp(-uExposure * value);
  outColor = vec4(vec3(pow(mapped, 1.0 / uGamma)), 1.0);
}
