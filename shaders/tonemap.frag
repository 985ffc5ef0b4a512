// HDR relative irradiance plus bloom -> exposure -> gamma -> 8-bit grey.
uniform sampler2D uHdr;
uniform sampler2D uBloom;
uniform float uBloomStrength;
uniform float uExposure;
uniform float uGamma;
layout(location = 0) out vec4 outColor;

void main() {
  float hdr = texelFetch(uHdr, ivec2(gl_FragCoord.xy), 0).r;
  float bloom = uBloomStrength > 0.0 ? texture(uBloom, gl_FragCoord.xy / vec2(textureSize(uHdr, 0))).r : 0.0;
  float mapped = 1.0 - exp(-uExposure * max(hdr + uBloomStrength * bloom, 0.0));
  outColor = vec4(vec3(pow(mapped, 1.0 / uGamma)), 1.0);
}
