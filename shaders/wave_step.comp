// SPDX-License-Identifier: LGPL-2.1-or-later
// One step of the pool's damped wave equation (docs/physics.md §14), the
// twin of WaveSolver::step in 32-bit floats:
//   (1 + a) h[n+1] = 2 h[n] - (1 - a) h[n-1] + C^2 L h[n] + dt^2 f,
// uKeep = 1 - a, uScale = 1 / (1 + a). The walls mirror the row inside.
// The wind's force is a sum of travelling waves, separable per wave into a
// row factor exp(i kx x) and a column factor exp(i ky y); uCoefficient
// carries each wave's amplitude and phase at this step, and uMean the
// force's trapezoidal mean (taken off so the wind keeps the volume).
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Before { float before[]; };
layout(std430, binding = 1) readonly buffer Now { float now[]; };
layout(std430, binding = 2) writeonly buffer Next { float next[]; };
layout(std430, binding = 3) readonly buffer Rows { vec2 rows[]; };        // [w * n + i]
layout(std430, binding = 4) readonly buffer Columns { vec2 columns[]; };  // [w * n + j]
uniform int uGrid;
uniform float uCourant2, uKeep, uScale;
uniform int uWaves;
uniform vec2 uCoefficient[32];
uniform float uMean;

int mirrored(int i) { return i < 0 ? -i : i >= uGrid ? 2 * (uGrid - 1) - i : i; }

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uGrid || p.y >= uGrid) return;
  int row = p.y * uGrid;
  float h = now[row + p.x];
  float laplacian = now[row + mirrored(p.x - 1)] + now[row + mirrored(p.x + 1)] + now[mirrored(p.y - 1) * uGrid + p.x] +
                    now[mirrored(p.y + 1) * uGrid + p.x] - 4.0 * h;
  // Im(exp(i (kx x + ky y)) c): the wave's dt^2 f here.
  float drive = -uMean;
  for (int w = 0; w < uWaves; ++w) {
    vec2 r = rows[w * uGrid + p.x], c = columns[w * uGrid + p.y];
    vec2 e = vec2(r.x * c.x - r.y * c.y, r.x * c.y + r.y * c.x);
    drive += e.x * uCoefficient[w].y + e.y * uCoefficient[w].x;
  }
  next[row + p.x] = (2.0 * h - uKeep * before[row + p.x] + uCourant2 * laplacian + drive) * uScale;
}
