// SPDX-License-Identifier: LGPL-2.1-or-later
// Tone-mapped RGBA -> I420 (BT.601, limited range), all three planes in one
// R8 target of width W and height 3H/2 whose rows are the buffer's memory
// order: Y (W x H), then U and V ((W/2) x (H/2) each, chroma averaged over
// each 2x2 block), packed without padding. Rows of the picture texture run
// bottom-up (GL), the planes top-down (video).
uniform sampler2D uPicture;
uniform ivec2 uSize;  // W, H of the picture
layout(location = 0) out float outByte;

vec3 rgb(ivec2 p) { return texelFetch(uPicture, ivec2(p.x, uSize.y - 1 - p.y), 0).rgb; }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int w = uSize.x, h = uSize.y;
  if (p.y < h) {
    outByte = 16.0 / 255.0 + dot(rgb(p), vec3(0.256788, 0.504129, 0.097906));
    return;
  }
  // Each row of the target past the Y plane holds two chroma rows (W/2
  // wide): rows 0..H/2-1 are U, then V. No integer division (scalar on a
  // CPU renderer).
  int half_w = w / 2;
  bool right = p.x >= half_w;
  int q = 2 * (p.y - h) + (right ? 1 : 0);  // chroma row over U then V
  bool is_v = q >= h / 2;
  if (is_v) q -= h / 2;
  ivec2 c = 2 * ivec2(right ? p.x - half_w : p.x, q);
  vec3 mean = 0.25 * (rgb(c) + rgb(c + ivec2(1, 0)) + rgb(c + ivec2(0, 1)) + rgb(c + ivec2(1, 1)));
  outByte = 128.0 / 255.0 + (is_v ? dot(mean, vec3(0.439216, -0.367788, -0.071427))
                                  : dot(mean, vec3(-0.148223, -0.290993, 0.439216)));
}
