// SPDX-License-Identifier: LGPL-2.1-or-later
// Receivers with a shape, whose light the server draws in their (u, v)
// atlas, one tile of the stream: a lathe (a vase, a bowl), or a mesh the
// scene brings (a folded cloth; its geometry comes with the scene,
// GET /api/v1/scenes/{id}, as receiver_meshes). three.js's LatheGeometry lays
// out (u, v) and splits each quad exactly as the server does
// (caustic/receiver_mesh.hpp), and a mesh carries its own, so the tile
// wraps back onto the same points of the surface.
import * as THREE from 'three';

const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);

// The geometry of receiver `r`; null for a rectangle, or a mesh whose
// shape `shapes` (name -> {positions, uvs, indices}) lacks.
export function shapeGeometry(r, shapes) {
  if (r.lathe) return new THREE.LatheGeometry(r.lathe.profile.map(([x, h]) => new THREE.Vector2(x, h)), r.lathe.segments);
  const m = r.mesh && shapes?.[r.mesh];
  if (!m) return null;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(m.positions, 3));
  g.setAttribute('uv', new THREE.Float32BufferAttribute(m.uvs, 2));
  g.setIndex(m.indices);
  g.computeVertexNormals();
  return g;
}

// The key a receiver's geometry depends on: rebuilt only when it changes.
export const shapeKey = (r) => (r.lathe ? JSON.stringify([r.lathe.profile, r.lathe.segments])
  : r.mesh ? `mesh ${r.mesh}` : 'rectangle');

// Local x, y, z of the geometry are the receiver's right, up (a lathe's
// axis) and normal (where a lathe's u starts), its origin the centre.
export function placeShape(meshes, s) {
  const normal = vec(s.normal).normalize();
  const up = vec(s.up).normalize();
  const right = new THREE.Vector3().crossVectors(up, normal).normalize();
  const basis = new THREE.Matrix4().makeBasis(right, up, normal);
  for (const m of meshes) {
    m.position.copy(vec(s.center));
    m.quaternion.setFromRotationMatrix(basis);
  }
}

// What a surface weighs in framing the view: a rectangle's area, a
// lathe's outline seen from the side, a mesh's extent across its normal.
export function surfaceArea(s, shapes) {
  if (s.lathe) {
    const radii = s.lathe.profile.map((p) => p[0]), heights = s.lathe.profile.map((p) => p[1]);
    return 2 * Math.max(...radii) * (Math.max(...heights) - Math.min(...heights) || 1);
  }
  const m = s.mesh && shapes?.[s.mesh];
  if (!m) return s.width * s.height;
  const box = new THREE.Box3().setFromArray(m.positions);
  return (box.max.x - box.min.x) * (box.max.y - box.min.y) || 1;
}
