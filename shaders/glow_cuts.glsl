// SPDX-License-Identifier: LGPL-2.1-or-later
// Where the glow stops (src/engine/glow.hpp): the edges of the atlas's
// tiles across and down, in glow texels from the bottom left, 0 and the
// glow's size included, so that no surface's light glows over a
// neighbouring tile. One surface: {0, size}.
const int kMaxCuts = 10;
uniform int uCutsX[kMaxCuts];
uniform int uCutsY[kMaxCuts];
uniform int uCutCountX;
uniform int uCutCountY;

// The texels [lo, hi) between the cuts around texel i.
ivec2 cutSegment(int cuts[kMaxCuts], int count, int i) {
  for (int k = 1; k < count - 1; ++k)
    if (i < cuts[k]) return ivec2(cuts[k - 1], cuts[k]);
  return ivec2(cuts[count - 2], cuts[count - 1]);
}

// The glow texels [lo, hi) of the tile holding glow texel p, across and down.
ivec4 glowTile(ivec2 p) {
  ivec2 x = cutSegment(uCutsX, uCutCountX, p.x), y = cutSegment(uCutsY, uCutCountY, p.y);
  return ivec4(x.x, y.x, x.y, y.y);
}
