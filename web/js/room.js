// SPDX-License-Identifier: LGPL-2.1-or-later
// What makes the glass read as glass: an environment to reflect (three.js's
// RoomEnvironment, generated in the page), a tiled table and plastered walls
// (canvas textures drawn here, nothing fetched), soft shadows, and a glass
// material that transmits with the object's thickness and index. Software
// WebGL may not keep up: the "low" quality drops the transmission pass and
// the shadows and draws a quarter of the pixels; the viewer starts with it
// on software WebGL and switches to it when the frame rate falls below 30.
import * as THREE from 'three';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';

export const Quality = Object.freeze({ high: 'high', low: 'low' });

// Mottling from a fixed seed: the same room on every visit (and screenshot).
function seeded(seed) {
  return () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}

// A canvas texture: `paint(context, size)` draws one repeat.
function canvasTexture(paint, repeat) {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 256;
  paint(canvas.getContext('2d'), 256);
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.repeat.set(repeat, repeat);
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.anisotropy = 4;
  return texture;
}

// A base colour with specks of light and shade (`count` squares of `size`
// pixels at `alpha`, from a fixed seed).
function mottle(g, n, { base, shade, count, size, alpha, seed }) {
  const random = seeded(seed);
  g.fillStyle = base;
  g.fillRect(0, 0, n, n);
  for (let i = 0; i < count; ++i) {
    g.fillStyle = `rgba(${random() < 0.5 ? '255,255,255' : shade},${alpha})`;
    g.fillRect(random() * n, random() * n, size, size);
  }
}

// Light stone tiles with darker joints and a little mottling, one tile a repeat.
const tiles = (g, n) => {
  mottle(g, n, { base: '#5e5b56', shade: '0,0,0', count: 1500, size: 6, alpha: 0.05, seed: 7 });
  g.strokeStyle = '#34322f';
  g.lineWidth = 4;
  g.strokeRect(0, 0, n, n);
};

// Warm plaster: a fine grain only.
const plaster = (g, n) => mottle(g, n, { base: '#8a847a', shade: '60,50,40', count: 4000, size: 3, alpha: 0.04, seed: 11 });

/// Adds environment, table and walls around `bounds` (scene coordinates:
/// screen, object and light) to `room`.
export function furnish(room, bounds) {
  const { scene, renderer } = room;
  const pmrem = new THREE.PMREMGenerator(renderer);
  room.environment = pmrem.fromScene(new RoomEnvironment(), 0.04).texture;
  pmrem.dispose();
  scene.environmentIntensity = 0.35;
  renderer.toneMapping = THREE.ACESFilmicToneMapping;
  renderer.shadowMap.type = THREE.PCFShadowMap;  // softened by shadow.radius

  const size = bounds.getSize(new THREE.Vector3());
  const span = 4 * Math.max(size.x, size.y, size.z);
  const tile = Math.max(size.x, size.z) / 3;  // a few tiles under the screen: they give the scale
  const table = surface(new THREE.PlaneGeometry(span, span), canvasTexture(tiles, span / tile), 0.8);
  table.rotation.x = -Math.PI / 2;
  table.position.set(bounds.getCenter(new THREE.Vector3()).x, bounds.min.y - 0.5, bounds.getCenter(new THREE.Vector3()).z);
  table.receiveShadow = true;
  const back = surface(new THREE.PlaneGeometry(span, span), canvasTexture(plaster, 3), 0.95);
  back.position.set(table.position.x, table.position.y + span / 2, table.position.z - span / 2);
  const left = surface(back.geometry, back.material.map, 0.95);
  left.rotation.y = Math.PI / 2;
  left.position.set(table.position.x - span / 2, back.position.y, table.position.z);
  back.receiveShadow = left.receiveShadow = true;
  scene.add(table, back, left);
  room.furniture = [table, back, left];

  // The sun's shadow covers the table around the screen.
  const sun = room.sun;
  sun.castShadow = true;
  sun.shadow.mapSize.set(1024, 1024);
  sun.shadow.radius = 4;
  const reach = span / 2;
  Object.assign(sun.shadow.camera, { left: -reach, right: reach, top: reach, bottom: -reach, near: 0.1, far: 4 * span });
  sun.shadow.camera.updateProjectionMatrix();
  sun.shadow.bias = -0.0005;
  setRoomQuality(room, room.quality);
}

// A surface of the room with a material for each quality: physically
// based, or Lambert (no environment lighting: a fraction of the cost in
// software GL).
function surface(geometry, map, roughness) {
  const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ map, roughness }));
  mesh.userData.materials = { [Quality.high]: mesh.material, [Quality.low]: new THREE.MeshLambertMaterial({ map }) };
  return mesh;
}

/// The furniture, the environment and the shadows for `quality`.
export function setRoomQuality(room, quality) {
  const high = quality === Quality.high;
  room.scene.environment = high ? room.environment ?? null : null;
  room.renderer.shadowMap.enabled = high;
  for (const thing of room.furniture ?? []) thing.material = thing.userData.materials[quality];
}

/// Glass of the object's index and the slab's thickness: transmissive, or
/// (low quality) merely see-through.
export function glassMaterial(quality, ior, thickness) {
  if (quality === Quality.low)
    return new THREE.MeshPhongMaterial({ color: 0xe8f4ff, shininess: 90, transparent: true, opacity: 0.2 });
  return new THREE.MeshPhysicalMaterial({ color: 0xffffff, transmission: 1, roughness: 0.03, metalness: 0, ior,
                                          thickness, specularIntensity: 1, attenuationColor: 0xe6f6ff,
                                          attenuationDistance: 40 * thickness, envMapIntensity: 1.2 });
}

/// Whether WebGL runs in software (SwiftShader, llvmpipe): the first guess
/// at the quality, before the frame rate has been measured. Multisampling,
/// which a canvas cannot drop later, is chosen from it.
export function softwareWebGL() {
  const gl = document.createElement('canvas').getContext('webgl2');
  if (!gl) return true;
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  gl.getExtension('WEBGL_lose_context')?.loseContext();
  return /swiftshader|llvmpipe|softpipe|software/i.test(name);
}

/// Device pixels per CSS pixel: the low path draws a quarter of the pixels
/// (software GL is bound by how many it fills) and lets the page scale them.
export function pixelRatio(quality) {
  return quality === Quality.high ? Math.min(window.devicePixelRatio, 2) : 0.5;
}
