// SPDX-License-Identifier: LGPL-2.1-or-later
// The keyboard's way to do what a drag does in the 3D view, for visitors
// who use no pointer: in orbit mode the arrows turn the camera round its
// target and + and - zoom; in light and move mode the arrows slide the
// light's marker or the object across the view and Page Up and Page Down
// raise and lower it; in rotate mode the arrows turn the object. Each step
// takes the same path as the gizmo's drag (the same callbacks, the same
// patches). With Shift an arrow or Page Up/Down takes a fifth of its step,
// for the fine placing a drag does by moving the pointer less. (+ and -
// have no fine step: Shift is how many keyboards type +.)
import * as THREE from 'three';

const TURN = THREE.MathUtils.degToRad(5);  // a step of orbit or rotation
const ZOOM = 1.15;                          // a step of zoom, as a factor of the distance
const MOVE = 0.03;                          // a step of a move, as a fraction of the camera's distance
const FINE = 0.2;                           // a Shift step, as a fraction of the step

const ARROWS = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
const UP_DOWN = { PageUp: 1, PageDown: -1 };

/// Listens for the keys on `target` (the window) and moves what `controls`
/// (a ControlModes) has in hand; `onLightMoved` and `onObjectMoved` are the
/// gizmo's own callbacks.
export function installViewKeys(controls, { onLightMoved, onObjectMoved }, target = window) {
  target.addEventListener('keydown', (e) => {
    // Typing in the panel, the browser's own keys (Ctrl and + zoom the
    // page), and a dialog's own keys are left alone.
    const t = e.target;
    if (t instanceof HTMLInputElement || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement) return;
    if (t instanceof Element && t.closest('[role=dialog]')) return;
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const scale = e.shiftKey ? FINE : 1;
    const done = controls.mode === 'none' ? orbitKey(controls.orbit, e.key, scale)
      : moveKey(controls, e.key, scale, controls.mode === 'light' ? onLightMoved : onObjectMoved);
    if (done) e.preventDefault();  // an arrow would scroll a scrollable page
  });
}

// The camera round the orbit's target, as a drag or the wheel would move
// it; `scale` is the fraction of a step the arrows take.
function orbitKey(orbit, key, scale) {
  const camera = orbit.object;
  const offset = camera.position.clone().sub(orbit.target);
  const spherical = new THREE.Spherical().setFromVector3(offset);
  if (ARROWS[key]) {
    const [right, up] = ARROWS[key];
    spherical.theta -= right * TURN * scale;
    spherical.phi = THREE.MathUtils.clamp(spherical.phi - up * TURN * scale, Math.max(orbit.minPolarAngle, 0.01),
                                          Math.min(orbit.maxPolarAngle, Math.PI - 0.01));
  } else if (key === '+' || key === '=' || key === '-' || key === '_') {
    const factor = key === '+' || key === '=' ? 1 / ZOOM : ZOOM;
    spherical.radius = THREE.MathUtils.clamp(spherical.radius * factor, orbit.minDistance, orbit.maxDistance);
  } else {
    return false;
  }
  camera.position.copy(orbit.target).add(offset.setFromSpherical(spherical));
  orbit.update();
  orbit.dispatchEvent({ type: 'end' });  // as a drag's end: the address follows the view
  return true;
}

// The gizmo's object (the light's marker or the object's handle), moved
// or turned one step (times `scale`) relative to the view, then reported
// as a drag is.
function moveKey(controls, key, scale, onMoved) {
  const object = controls.gizmo.object;
  if (!object || (!ARROWS[key] && !UP_DOWN[key])) return false;
  const camera = controls.orbit.object;
  const up = new THREE.Vector3(0, 1, 0);
  // The view's right and its forward along the table.
  const forward = camera.getWorldDirection(new THREE.Vector3()).setY(0);
  if (forward.lengthSq() < 1e-9) forward.set(0, 0, -1).applyQuaternion(camera.quaternion).setY(0);
  forward.normalize();
  const right = forward.clone().cross(up).normalize();
  const parent = object.parent;
  parent.updateMatrixWorld();
  if (controls.mode === 'rotate') {
    if (!ARROWS[key]) return false;
    const [dx, dy] = ARROWS[key];
    const axis = dx ? up : right;  // left and right about the vertical, up and down tip it towards the view
    const local = axis.clone().transformDirection(parent.matrixWorld.clone().invert());
    object.quaternion.premultiply(new THREE.Quaternion().setFromAxisAngle(local, (dx || -dy) * TURN * scale));
  } else {
    const step = MOVE * scale * camera.position.distanceTo(controls.orbit.target);
    const [dx, dy] = ARROWS[key] ?? [0, 0];
    const move = right.multiplyScalar(dx * step).addScaledVector(forward, dy * step)
      .addScaledVector(up, (UP_DOWN[key] ?? 0) * step);
    const at = object.getWorldPosition(new THREE.Vector3()).add(move);
    object.position.copy(parent.worldToLocal(at));
  }
  onMoved();
  return true;
}
