// SPDX-License-Identifier: LGPL-2.1-or-later
// A lathe receiver (a vase, a bowl): a surface of revolution whose light
// the server draws in its (u, v) atlas, one tile of the stream. three.js's
// LatheGeometry lays out (u, v) and splits each quad exactly as the server
// does (caustic/receiver_mesh.hpp), so the tile wraps back onto the same
// points of the surface.
import * as THREE from 'three';

const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);

export function latheGeometry(lathe) {
  return new THREE.LatheGeometry(lathe.profile.map(([r, h]) => new THREE.Vector2(r, h)), lathe.segments);
}

// The key a lathe's geometry depends on: rebuilt only when it changes.
export const latheKey = (lathe) => JSON.stringify([lathe.profile, lathe.segments]);

// Local x, y, z of the geometry are the receiver's right, up (its axis) and
// normal (where u starts), its origin the centre of its base.
export function placeLathe(meshes, s) {
  const normal = vec(s.normal).normalize();
  const up = vec(s.up).normalize();
  const right = new THREE.Vector3().crossVectors(up, normal).normalize();
  const basis = new THREE.Matrix4().makeBasis(right, up, normal);
  for (const m of meshes) {
    m.position.copy(vec(s.center));
    m.quaternion.setFromRotationMatrix(basis);
  }
}

// What a surface weighs in framing the view: a rectangle's area, or the
// lathe's outline seen from the side.
export function surfaceArea(s) {
  if (!s.lathe) return s.width * s.height;
  const radii = s.lathe.profile.map((p) => p[0]), heights = s.lathe.profile.map((p) => p[1]);
  return 2 * Math.max(...radii) * (Math.max(...heights) - Math.min(...heights) || 1);
}
