// SPDX-License-Identifier: LGPL-2.1-or-later
// Exposure metering, step 1 on the GPU: every uStride-th pixel across and
// down (after the local operator's compression, when on) into a small float
// image that the CPU bins (src/scene/exposure.cpp, with the same stride and
// bins as the CPU twin the tests use). A histogram built on the GPU would
// need atomics, which a CPU renderer runs slowly; a 256^2 read-back is cheap.
uniform sampler2D uHdr;
uniform int uStride;
layout(location = 0) out float outValue;

void main() {
  ivec2 p = uStride * ivec2(gl_FragCoord.xy);
  outValue = luminance(texelFetch(uHdr, p, 0).rgb) * local_factor((vec2(p) + 0.5) / vec2(textureSize(uHdr, 0)));
}
