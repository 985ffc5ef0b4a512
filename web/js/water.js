// SPDX-License-Identifier: LGPL-2.1-or-later
// The pool's water (scenes with a `water` section): the server simulates
// the surface, and every frame's message on the "frames" channel carries a
// coarse copy of the surface that frame's caustic came from. A page draws
// that copy over the floor when the frame is shown, so the ripples and the
// caustic under them agree (ShownWater: the viewer and a broadcast's
// viewers). In the viewer a click on the water also drops a stone there
// (POST .../drops), and the panel pauses the water and sets its rain
// (PoolWater).
import * as THREE from 'three';

import { postDrop } from './api.js';

// A click is a press and release this close together (CSS pixels): more is
// a drag, which orbits the camera.
const CLICK_SLOP_PX = 6;
// How long a refused drop's reason stays on the page.
const REFUSAL_SHOWN_MS = 6000;
// Ripples millimetres high on a pool metres across are flat to the eye: the
// surface is drawn at its true heights, but shaded as if its slopes were
// this many times steeper, so that its glints show the ripples.
const SHADING_RELIEF = 25;

/// Heights in metres from a frame's water message: n*n little-endian int16
/// times `unit`, row-major with y the slow index (docs/api.md).
export function decodeHeights({ n, unit, heights }) {
  const text = atob(heights);
  const out = new Float32Array(n * n);
  for (let k = 0; k < out.length && 2 * k + 1 < text.length; ++k) {
    const u = text.charCodeAt(2 * k) | (text.charCodeAt(2 * k + 1) << 8);
    out[k] = (u >= 0x8000 ? u - 0x10000 : u) * unit;
  }
  return out;
}

// Water as the eye takes it, cheap enough for software GL: see-through and
// tinted when looked into, a mirror of the sky towards grazing (Schlick's
// Fresnel, a little stronger than water's 2 % so that it shows from above),
// and the sun's glints off the ripples' flanks.
const vertexShader = `
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec4 world = modelMatrix * vec4(position, 1.0);
  vWorld = world.xyz;
  vNormal = normalize(mat3(modelMatrix) * normal);
  gl_Position = projectionMatrix * viewMatrix * world;
}`;
const fragmentShader = `
uniform vec3 tint;
uniform vec3 zenith;
uniform vec3 horizon;
uniform vec3 sunDirection;  // towards the sun (the room's light)
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec3 n = normalize(vNormal);
  vec3 v = normalize(cameraPosition - vWorld);
  if (dot(n, v) < 0.0) n = -n;  // seen from under the water
  float fresnel = 0.1 + 0.9 * pow(1.0 - clamp(dot(n, v), 0.0, 1.0), 5.0);
  vec3 r = reflect(-v, n);
  vec3 sky = mix(horizon, zenith, smoothstep(0.3, 1.0, r.y));
  float glint = 1.5 * pow(max(dot(r, sunDirection), 0.0), 120.0);
  gl_FragColor = vec4(mix(tint, sky, fresnel) + glint, clamp(0.22 + 0.78 * fresnel + glint, 0.0, 1.0));
  #include <tonemapping_fragment>
  #include <colorspace_fragment>
}`;

/// The drawn surface: a grid of the message's n x n posts over the pool,
/// `size` metres square, centred on the object's origin (the water's own
/// coordinates: x, y across, z up), in place of the object's slab.
export class WaterSurface {
  constructor(room, size) {
    this.room = room;
    this.size = size;
    // Drawn after the floor, which shows through it.
    this.material = new THREE.ShaderMaterial({
      vertexShader, fragmentShader, transparent: true, depthWrite: false, side: THREE.DoubleSide,
      uniforms: { tint: { value: new THREE.Color(0x1f6f8c) }, zenith: { value: new THREE.Color(0xf0f8ff) },
                  horizon: { value: new THREE.Color(0x2c4452) }, sunDirection: { value: new THREE.Vector3(0, 1, 0) } } });
    this.mesh = new THREE.Mesh(this.grid(2), this.material);
    this.mesh.renderOrder = 3;
    // The sun's direction as the room last placed its light.
    this.mesh.onBeforeRender = () => {
      const sun = room.sun.getWorldPosition(new THREE.Vector3()).sub(room.sun.target.getWorldPosition(new THREE.Vector3()));
      this.material.uniforms.sunDirection.value.copy(sun.normalize());
    };
    // The pool's rim: where the water ends (a click beyond it drops nothing).
    const rim = new THREE.EdgesGeometry(new THREE.PlaneGeometry(size, size));
    this.rim = new THREE.LineSegments(rim, new THREE.LineBasicMaterial({ color: 0x9fc8dc, transparent: true, opacity: 0.7 }));
    room.proxy.visible = false;
    room.drawnPose.add(this.mesh, this.rim);
    this.n = 2;
  }

  // A flat n x n grid. PlaneGeometry lists its rows from +y down, the
  // message from -y up: show() maps one onto the other.
  grid(n) {
    return new THREE.PlaneGeometry(this.size, this.size, n - 1, n - 1);
  }

  /// Draws the heights of one message (metres, decodeHeights).
  show(n, heights) {
    if (n !== this.n) {
      this.mesh.geometry.dispose();
      this.mesh.geometry = this.grid(n);
      this.n = n;
    }
    const { position, normal } = this.mesh.geometry.attributes;
    const h = (i, j) => heights[THREE.MathUtils.clamp(j, 0, n - 1) * n + THREE.MathUtils.clamp(i, 0, n - 1)];
    const slope = SHADING_RELIEF * (n - 1) / (2 * this.size);  // central differences, one-sided at the walls
    const v = new THREE.Vector3();
    for (let row = 0; row < n; ++row) {
      const j = n - 1 - row;
      for (let i = 0; i < n; ++i) {
        position.setZ(row * n + i, h(i, j));
        v.set(-slope * (h(i + 1, j) - h(i - 1, j)), -slope * (h(i, j + 1) - h(i, j - 1)), 1).normalize();
        normal.setXYZ(row * n + i, v.x, v.y, v.z);
      }
    }
    position.needsUpdate = normal.needsUpdate = true;
    this.mesh.geometry.computeBoundingSphere();  // for the click's raycast
    this.mesh.geometry.computeBoundingBox();
  }

  /// Where a page point (CSS pixels) meets the water, in the water's own
  /// coordinates [x, y], or null when it misses.
  hit(clientX, clientY) {
    const canvas = this.room.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - canvas.left) / canvas.width) * 2 - 1,
                                  1 - ((clientY - canvas.top) / canvas.height) * 2);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.room.camera);
    const [first] = ray.intersectObject(this.mesh, false);
    if (!first) return null;
    const p = this.mesh.worldToLocal(first.point.clone());
    // The grid's edge is the pool's wall: a hit may round a hair beyond it.
    const half = this.size / 2;
    return [THREE.MathUtils.clamp(p.x, -half, half), THREE.MathUtils.clamp(p.y, -half, half)];
  }
}

/// The surface drawn from the shown frames' water messages, and what the
/// page knows of it (`record`: the last drawn step, drops and n, and how
/// many surfaces were drawn; read by the tests as window.caustic.water).
/// Placing it hides the object's slab. A broadcast's viewers only watch.
export class ShownWater {
  constructor(room, water) {
    this.surface = new WaterSurface(room, water.size);
    this.record = { step: null, drops: null, n: null, updates: 0 };
  }

  /// A frame's message, when that frame is shown.
  show(message) {
    this.surface.show(message.n, decodeHeights(message));
    Object.assign(this.record, { step: message.step, drops: message.drops, n: message.n });
    this.record.updates += 1;
  }
}

/// The water of a viewer: the shown surface, clicks that drop stones, and
/// what the page knows of them (`record`, besides ShownWater's).
/// `session()` is the current session (it changes on reconnect),
/// `onRefused(problem or null)` shows or clears a refused drop's reason.
export class PoolWater extends ShownWater {
  constructor(room, controls, water, { session, onRefused }) {
    super(room, water);
    this.session = session;
    this.onRefused = onRefused;
    // lastDrop: the last accepted drop, with the surfaces drawn (updates)
    // and the time when the server accepted it and when a frame showed it.
    Object.assign(this.record, { posted: 0, lastDrop: null, refused: null });
    // A press on a gizmo's handle drags the light or the object, wherever it ends.
    const gizmo = controls.gizmo;
    this.listen(room.renderer.domElement, () => gizmo.dragging || (gizmo.object !== undefined && gizmo.axis !== null));
    // The keyboard's click: D drops a stone where the middle of the view
    // meets the water (the arrows turn the view over the pool).
    window.addEventListener('keydown', (e) => {
      if (e.key !== 'd' && e.key !== 'D') return;
      if (e.ctrlKey || e.metaKey || e.altKey || e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
      const view = room.renderer.domElement.getBoundingClientRect();
      this.click(view.left + view.width / 2, view.top + view.height / 2);
    });
  }

  show(message) {
    super.show(message);
    const last = this.record.lastDrop;
    if (last && last.shownAt === null && message.drops >= last.drop)
      Object.assign(last, { shownAt: this.record.updates, shownMs: performance.now() });
  }

  // A press and release of the primary pointer with no drag between is a
  // click; a second finger (a pinch) or a press on a gizmo is not.
  listen(canvas, busy) {
    let down = null;
    canvas.addEventListener('pointerdown', (e) => {
      down = e.isPrimary && e.button === 0 && !busy() ? { x: e.clientX, y: e.clientY, id: e.pointerId } : null;
    });
    canvas.addEventListener('pointerup', (e) => {
      if (!down || e.pointerId !== down.id) return;
      const moved = Math.hypot(e.clientX - down.x, e.clientY - down.y);
      down = null;
      if (moved <= CLICK_SLOP_PX) this.click(e.clientX, e.clientY);
    });
    canvas.addEventListener('pointercancel', () => { down = null; });
  }

  /// A click at a page point: a drop where it meets the water. Resolves to
  /// the server's answer ({ status, body }), or null when it missed.
  click(clientX, clientY) {
    const point = this.surface.hit(clientX, clientY);
    return point ? this.drop(point[0], point[1]) : Promise.resolve(null);
  }

  async drop(x, y) {
    const session = this.session();
    if (!session) return null;
    this.record.posted += 1;
    let answer;
    try {
      answer = await postDrop(session, { x, y });
    } catch (error) {
      answer = { ok: false, status: 0, body: { detail: error.message } };
    }
    if (answer.ok) {
      // The frame with the drop may have been shown before this answer came.
      const { updates, drops } = this.record, now = performance.now(), shown = drops >= answer.body.drop;
      this.record.lastDrop = { drop: answer.body.drop, acceptedAt: updates, acceptedMs: now,
                               shownAt: shown ? updates : null, shownMs: shown ? now : null };
      if (this.record.refused) this.refuse(null);
    } else {
      // The server's detail names the key at fault.
      this.refuse({ key: 'drop', detail: answer.body.detail ?? `the server answered ${answer.status}` });
    }
    return { status: answer.status, body: answer.body };
  }

  // Shows a refusal for a while (each refusal restarts the wait), or clears it.
  refuse(problem) {
    this.record.refused = problem;
    clearTimeout(this.refusalTimer);
    this.onRefused(problem);
    if (problem) this.refusalTimer = setTimeout(() => this.refuse(null), REFUSAL_SHOWN_MS);
  }

  /// The panel's "Water" folder: pause and the rain, through the viewer's
  /// coalesced patches (`send(key)` makes a controller's onChange).
  addFolder(gui, water, send) {
    const folder = gui.addFolder('Water');
    folder.add(water, 'paused').name('paused').onChange(send('paused'));
    folder.add(water, 'rain_strength', 0, 0.02, 0.0005).name('wave strength (m)').onChange(send('rain_strength'));
    folder.add(water, 'rain_rate', 0, 50, 0.5).name('rain (drops/s)').onChange(send('rain_rate'));
    return folder;
  }
}
