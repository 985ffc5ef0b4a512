// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's panel (lil-gui): each control sends its key as a patch on
// the parameter channel of the moment (`channel()`: a reconnect replaces it).
import GUI from 'lil-gui';

import { Quality } from './room.js';

// The panel's name for object.glass: a catalogue name, "none", or "custom"
// for coefficients (shown, not offered).
const glassName = (glass) => (glass === null || glass === undefined ? 'none' : typeof glass === 'string' ? glass : 'custom');

/// `state` is the viewer's (its params are what the controllers edit);
/// `parts`: { channel, room, controls, water } (functions for what a
/// reconnect replaces or the room's start makes), resetScene(),
/// onCodec() (the codec changed: connect again), statsPanel.
export class Panel {
  constructor(state, parts) {
    this.state = state;
    this.parts = parts;
    this.colour = { glass: 'none' };  // object.glass as the dropdown shows it
    this.build();
  }

  /// The controllers show `params` (an answer the server gave).
  refresh(params) {
    for (const section of ['object', 'light', 'screen', 'render', 'post', 'water'])
      if (params[section] && this.params[section]) Object.assign(this.params[section], params[section]);
    this.colour.glass = glassName(params.object.glass);
    this.gui.controllersRecursive().forEach((c) => c.updateDisplay());
  }

  build() {
    const { state, parts, colour } = this;
    const channel = () => parts.channel();
    const gui = this.gui = new GUI({ title: 'Caustic' });
    // A landmark for screen readers: the settings, beside the header and the view.
    gui.domElement.setAttribute('role', 'region');
    gui.domElement.setAttribute('aria-label', 'Settings');
    // A phone's screen is the picture's: the panel starts folded there.
    if (matchMedia('(max-width: 720px)').matches) gui.close();
    const p = this.params = state.params;
    gui.add({ resetView: () => parts.controls().orbit.reset() }, 'resetView').name('Reset view');
    gui.add({ resetScene: parts.resetScene }, 'resetScene').name('Reset scene');
    const send = (section, key) => (value) => channel().set({ [section]: { [key]: value } });
    const material = gui.addFolder('Material');
    material.add(p.object, 'material', ['refractive', 'reflective']).onChange(send('object', 'material'));
    material.add(p.object, 'ior', 1.0, 3.0, 0.01).onChange(send('object', 'ior'));
    // A glass disperses: the frame turns to colour, one pass per wavelength.
    // "none" (not null, which would restore the scene's own glass) removes it.
    colour.glass = glassName(p.object.glass);
    const glasses = ['none', ...(state.glasses ?? [])];
    if (!glasses.includes(colour.glass)) glasses.push(colour.glass);
    material.add(colour, 'glass', glasses).name('glass (dispersion)').onChange((glass) => {
      if (glass !== 'custom') channel().set({ object: { glass } });
    });
    const light = gui.addFolder('Light');
    light.add(p.light, 'type', ['directional', 'point']).onChange((type) => {
      channel().set({ light: { type, ...parts.room().lightFromMarker(type) } });
    });
    light.add(p.light, 'spectrum', ['d65', 'e', 'blackbody', 'led']).name('spectrum (with a glass)')
      .onChange(send('light', 'spectrum'));
    light.add(p.light, 'temperature_k', 1000, 40000, 100).name('blackbody (K)').onChange(send('light', 'temperature_k'));
    const quality = gui.addFolder('Quality');
    quality.add(p.render, 'fidelity', ['auto', 'manual']).onChange(send('render', 'fidelity'));
    quality.add(p.render, 'accuracy_target', 0.001, 0.2, 0.001).name('target L1 (auto)').onChange(send('render', 'accuracy_target'));
    quality.add(p.render, 'mesh_resolution', state.fidelity.levels).name('mesh level (manual)')
      .onChange((n) => channel().set({ render: { mesh_resolution: Number(n) } }));
    quality.add(p.render, 'fresnel').name('Fresnel (manual)').onChange(send('render', 'fresnel'));
    quality.add(p.render, 'wavelengths', 1, 32, 1).name('wavelengths (glass)').onChange(send('render', 'wavelengths'));
    quality.add(p.render, 'still_wavelengths', 1, 32, 1).name('… when still').onChange(send('render', 'still_wavelengths'));
    const post = gui.addFolder('Post-processing');
    post.add(p.post, 'exposure_mode', ['auto', 'manual']).name('exposure').onChange(send('post', 'exposure_mode'));
    // In "auto" the value is exposure compensation (1 = as metered): a log slider would suit,
    // but a plain range from 1/20 to 20 keeps lil-gui's own control.
    post.add(p.post, 'exposure', 0.05, 20, 0.01).name('exposure value / comp.').onChange(send('post', 'exposure'));
    post.add(p.post, 'tone_map', ['global', 'local']).name('tone map').onChange(send('post', 'tone_map'));
    post.add(p.post, 'local_strength', 0, 1, 0.01).name('local strength').onChange(send('post', 'local_strength'));
    post.add(p.post, 'gamma', 0.5, 4, 0.01).onChange(send('post', 'gamma'));
    post.add(p.post, 'bloom_strength', 0, 2, 0.01).onChange(send('post', 'bloom_strength'));
    post.add(p.post, 'bloom_threshold', 0, 10, 0.1).onChange(send('post', 'bloom_threshold'));
    post.add(p.post, 'bloom_radius', 0, 32, 0.5).onChange(send('post', 'bloom_radius'));
    const water = parts.water();
    if (water && p.water) water.addFolder(gui, p.water, (key) => send('water', key));
    const view = gui.addFolder('Stream');
    view.add(state, 'codec', ['vp8', 'h264']).onChange(parts.onCodec);
    view.add(state, 'sync').name('synchronous pose');
    view.add(state, 'quality', Object.values(Quality)).name('room quality')
      .onChange((q) => parts.room().setQuality(q)).listen();
    view.add({ stats: false }, 'stats').name('stats overlay').onChange((on) => { parts.statsPanel.hidden = !on; });
  }
}
