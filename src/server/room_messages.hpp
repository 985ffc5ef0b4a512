// SPDX-License-Identifier: LGPL-2.1-or-later
// What a broadcast's viewers draw the room from. A one-viewer page reads
// its session's params and atlas over REST; a broadcast's viewers hold no
// session token, so the server tells them on the data channel Janus
// relays, in datagrams that Janus passes whole only up to 1,500 bytes: the
// room (screen, light, the object's pose, a pool's size, the picture's size
// and the screen's tile of it) in one message, and each receiver (a floor,
// a wall, a lathe's profile, a mesh shape's name) with its tile in one of
// its own, since a lathe's profile alone can fill most of a datagram. A
// receiver's numbers are rounded to 1e-4 (a tenth of a micrometre in
// millimetres; a drawing needs no more), or as far as a lathe of the most
// profile points at the largest coordinates needs to fit (whole units at
// worst, a millionth of its size); the room's stay exact (a viewer shows
// the holder's values).
#pragma once

#include "caustic/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace caustic::server {

/// Janus's 1,500 bytes less room for its own framing.
inline constexpr std::size_t kRoomDatagramBytes = 1400;

/// `{"params": {light, screen, object: {position, rotation_deg, ior},
/// water?: {size}, render: {width, height}, receiver_count, tile}, "version"}`
/// then, for each receiver i, `{"receiver": {index, count, tile, surface},
/// "version"}`: `surface` as the scene format writes a receiver, `tile` its
/// part of the picture ({x, y, width, height}, rows from the top).
std::vector<std::string> room_messages(const Scene& scene, std::uint64_t version);

}  // namespace caustic::server
