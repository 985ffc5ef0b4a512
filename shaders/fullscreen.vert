// SPDX-License-Identifier: LGPL-2.1-or-later
// One triangle that covers the viewport; no vertex buffer needed.
out vec2 vUv;

void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vUv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
