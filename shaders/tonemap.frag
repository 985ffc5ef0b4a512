// SPDX-License-Identifier: LGPL-2.1-or-later
// HDR relative irradiance plus bloom -> local compression (when on) ->
// exposure -> gamma -> 8-bit RGB (grey for a monochrome frame). A preview's HDR image is smaller than the
// output: it is upsampled here (bilinear); a full frame reads its texel
// exactly.
uniform sampler2D uHdr;
uniform vec2 uOutputSize;
uniform sampler2D uBloom;
uniform float uBloomStrength;
uniform int uShrink;  // the glow's texels per picture pixel, each way
uniform float uExposure;
uniform float uGamma;
uniform bool uGrey;  // a monochrome frame: R = G = B, mapped once
layout(location = 0) out vec4 outColor;

void main() {
  vec2 uv = gl_FragCoord.xy / uOutputSize;
  vec3 hdr = textureSize(uHdr, 0) == ivec2(uOutputSize) ? texelFetch(uHdr, ivec2(gl_FragCoord.xy), 0).rgb
                                                        : texture(uHdr, uv).rgb;
  vec3 bloom = vec3(0.0);
  if (uBloomStrength > 0.0) {
    // Sampled within the tile of the picture's pixel under this one
    // (glow_cuts.glsl): bilinear filtering stops at the tile's texel centres.
    ivec2 hdrSize = textureSize(uHdr, 0), glowSize = textureSize(uBloom, 0);
    ivec2 pixel = min(ivec2(uv * vec2(hdrSize)), hdrSize - 1);
    ivec4 tile = glowTile(min(pixel / uShrink, glowSize - 1));
    vec2 at = clamp(uv * vec2(glowSize), vec2(tile.xy) + 0.5, vec2(tile.zw) - 0.5);
    bloom = texture(uBloom, at / vec2(glowSize)).rgb;
  }
  // Per channel: a saturated colour too bright for the screen desaturates
  // towards white, as film and eyes show it, instead of clipping its hue.
  vec3 value = max(hdr + uBloomStrength * bloom, 0.0) * local_factor(uv);
  if (uGrey) {  // a third of the transcendental work, which dominates this pass on a CPU renderer
    float grey = 1.0 - exp(-uExposure * value.r);
    if (uGamma != 1.0) grey = pow(grey, 1.0 / uGamma);  // a uniform branch: linear output skips the pow
    outColor = vec4(vec3(grey), 1.0);
    return;
  }
  vec3 mapped = 1.0 - exp(-uExposure * value);
  outColor = vec4(pow(mapped, vec3(1.0 / uGamma)), 1.0);
}
