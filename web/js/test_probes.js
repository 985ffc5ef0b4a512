// SPDX-License-Identifier: LGPL-2.1-or-later
// What the test hooks of both pages (test_hooks.js, watch_test_hooks.js)
// read off the drawn room: computed here from the room's own objects, so
// that no page logic exists only for the tests.
import * as THREE from 'three';

/// Each surface's lightmap: where it hangs, its shape and which part of the picture it shows.
export function surfaceTiles(room) {
  return [room.lightmap, ...room.receivers.map((r) => r.lightmap)].map((m) => ({
    centre: m.position.toArray(), offset: m.material.map.offset.toArray(), repeat: m.material.map.repeat.toArray(),
    shape: m.geometry.type,
  }));
}

/// Where the slab's middle is drawn, in scene coordinates.
export function drawnCentre(room) {
  return room.world.worldToLocal(room.proxy.getWorldPosition(new THREE.Vector3())).toArray();
}

// A world point on the page, in CSS pixels.
function onPage(room, point) {
  const p = point.project(room.camera);
  const r = room.renderer.domElement.getBoundingClientRect();
  return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
}

/// Where an object of the room is drawn on the page.
export const pagePoint = (room, object) => onPage(room, object.getWorldPosition(new THREE.Vector3()));

/// Where the water's point (x, y) at height z (0: the still surface) is on the page.
export const waterPagePoint = (surface, x, y, z = 0) =>
  onPage(surface.room, surface.mesh.localToWorld(new THREE.Vector3(x, y, z)));

/// A water surface's heights as drawn (metres, the frame message's order).
export function drawnHeights(surface) {
  const position = surface.mesh.geometry.attributes.position;
  const n = surface.n, out = [];
  for (let j = 0; j < n; ++j)
    for (let i = 0; i < n; ++i) out.push(position.getZ((n - 1 - j) * n + i));
  return out;
}
