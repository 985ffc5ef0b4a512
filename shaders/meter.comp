// Exposure metering: a histogram of the lit pixels' log2 value (after the
// local operator's compression, when on), binned exactly as the CPU twin in
// src/scene/exposure.cpp. Each invocation reads 2x2 pixels into a shared
// histogram; a workgroup then adds its non-empty bins to the global one.
layout(local_size_x = 16, local_size_y = 16) in;
uniform sampler2D uHdr;
uniform float uLog2Lit;
uniform float uBinsPerStop;
layout(std430, binding = 1) buffer Histogram { uint bins[256]; };
shared uint local_bins[256];

void main() {
  uint i = gl_LocalInvocationIndex;
  local_bins[i] = 0u;
  barrier();
  ivec2 size = textureSize(uHdr, 0);
  for (int d = 0; d < 4; ++d) {
    ivec2 p = 2 * ivec2(gl_GlobalInvocationID.xy) + ivec2(d & 1, d >> 1);
    if (p.x >= size.x || p.y >= size.y) continue;
    float h = texelFetch(uHdr, p, 0).r * local_factor((vec2(p) + 0.5) / vec2(size));
    if (!(h > exp2(uLog2Lit))) continue;
    int bin = int((log2(h) - uLog2Lit) * uBinsPerStop);
    atomicAdd(local_bins[clamp(bin, 0, 255)], 1u);
  }
  barrier();
  if (local_bins[i] > 0u) atomicAdd(bins[i], local_bins[i]);
}
