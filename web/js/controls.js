// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's control modes as a state machine (the report's design): at
// any time exactly one of none, light translation, object translation and
// object rotation is active, and only its gizmo and helpers are visible.
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { TransformControls } from 'three/addons/controls/TransformControls.js';

import { installViewKeys } from './keyboard_view.js';

export const Modes = Object.freeze({ none: 'none', light: 'light', move: 'move', rotate: 'rotate' });

export class ControlModes {
  constructor(room, { onLightMoved, onObjectMoved, onModeChanged }) {
    this.room = room;
    this.orbit = new OrbitControls(room.camera, room.renderer.domElement);
    this.orbit.target.set(0, -20, 0);
    this.orbit.update();
    this.gizmo = new TransformControls(room.camera, room.renderer.domElement);
    room.scene.add(this.gizmo.getHelper());
    this.gizmo.addEventListener('dragging-changed', (e) => { this.orbit.enabled = !e.value; });
    this.gizmo.addEventListener('objectChange', () => {
      if (this.mode === Modes.light) onLightMoved();
      else onObjectMoved();
    });
    this.onModeChanged = onModeChanged;
    window.addEventListener('keydown', (e) => {
      if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;  // typing in the panel
      if (e.ctrlKey || e.metaKey || e.altKey) return;  // the browser's own (Ctrl+R reloads)
      const next = { l: Modes.light, t: Modes.move, r: Modes.rotate, Escape: Modes.none, 0: Modes.none }[e.key];
      if (next) this.set(next);
    });
    installViewKeys(this, { onLightMoved, onObjectMoved });
    // The toolbar: the same modes for touch and pointer.
    this.buttons = [...document.querySelectorAll('#modes [data-mode]')];
    for (const button of this.buttons) button.addEventListener('click', () => this.set(button.dataset.mode));
    this.set(Modes.none);
  }

  set(mode) {
    this.mode = mode;
    this.gizmo.detach();
    const light = mode === Modes.light;
    this.room.lightArrow.visible = light;
    if (light) this.gizmo.attach(this.room.lightMarker);
    if (mode === Modes.move || mode === Modes.rotate) this.gizmo.attach(this.room.handle);
    this.gizmo.setMode(mode === Modes.rotate ? 'rotate' : 'translate');
    this.gizmo.getHelper().visible = mode !== Modes.none;
    for (const button of this.buttons) button.setAttribute('aria-pressed', String(button.dataset.mode === mode));
    this.onModeChanged(mode);
  }
}
