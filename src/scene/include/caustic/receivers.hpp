// SPDX-License-Identifier: LGPL-2.1-or-later
// The surfaces that catch the light: the screen and scene.receivers (a
// floor, walls, a table), each a rectangle, or a lathe (a vase,
// caustic/receiver_mesh.hpp) whose tile is its (u, v) atlas. A ray lands
// on the first one it meets, so one surface shades another. The picture is
// their atlas: each surface's irradiance in its own tile, streamed as one
// video, which the viewer cuts up again onto the surfaces in its room.
//
// Alone, the screen keeps its old meaning, the whole plane: light that
// lands beside the rectangle is simply outside the picture. With receivers
// every surface is its rectangle, so light that misses one goes on to the
// next.
#pragma once

#include "caustic/scene.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace caustic {

/// A tile in pixels, rows counted from the top of the picture.
struct AtlasTile {
  int x = 0, y = 0, width = 0, height = 0;
  bool operator==(const AtlasTile&) const = default;
};

/// Tiles of a width x height picture for `count` surfaces in the order
/// screen, receivers[0], receivers[1], ...: the whole picture for one;
/// otherwise a grid of ceil(sqrt(count)) columns filled row by row from
/// the top left, every tile the same size (pixels left over at the right
/// and bottom edges stay black).
std::vector<AtlasTile> atlas_layout(int width, int height, std::size_t count);

/// Orthonormal axes of a screen or receiver: right = up x normal, so a
/// viewer facing it (looking along -normal) sees +right to the right.
glm::dvec3 screen_right(const ScreenParams& screen);

/// The screen, then the receivers.
std::vector<ScreenParams> receiving_surfaces(const Scene& scene);

struct ReceiverHit {
  int index = -1;             ///< into receiving_surfaces; -1: none
  glm::dvec2 local{0.0};      ///< (right, up) from the surface's centre, world units; a lathe's or mesh's (u, v) - 0.5
  double distance = 0;        ///< along the ray
  int element = -1;           ///< a lathe's or mesh's triangle hit (ReceiverMesh::stretch); -1 on a rectangle
};

/// World area per unit of `local` area where a ray landed on `surface`
/// (triangle `element` of a lathe or mesh; 1 on a rectangle).
inline double surface_stretch(const ScreenParams& surface, int element) {
  return surface.body() && element >= 0 ? surface.body()->stretch(element) : 1.0;
}

/// Whether scene's receivers include a shape the GL's shaders cannot land
/// on (a lathe, a mesh): its rays then land and deposit on the CPU.
bool has_shaped_receiver(const Scene& scene);

/// The first surface the ray from `origin` along `dir` meets ahead of it.
ReceiverHit first_receiver(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& dir);

}  // namespace caustic
