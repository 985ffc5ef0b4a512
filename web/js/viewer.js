// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer: starts a session for ?scene=ID&codec=vp8|h264, shows the
// streamed caustic on the lightmap plane (and a pool's water, water.js), and
// turns the controls into coalesced parameter patches.
import GUI from 'lil-gui';
import { createSession, deleteSession, ParamChannel, Refused, ServerFull } from './api.js';
import { ControlModes } from './controls.js';
import { LoadingSteps } from './loading.js';
import { retryAfter } from './retry.js';
import { FrameRate, Quality, softwareWebGL } from './room.js';
import { CausticRoom } from './scene3d.js';
import { changedParams, sharedParams, sharedView, writeAddress } from './share.js';
import { showStats } from './stats_overlay.js';
import { Stream } from './stream.js';
import { installTestHooks } from './test_hooks.js';
import { PoolWater } from './water.js';

const query = new URLSearchParams(location.search);
const sceneId = query.get('scene') ?? 'wavy';
// A visitor's design lives on one instance behind a proxy: the page asks
// that one for the scene and the session (docs/scaling.md).
const home = /^[0-9]{1,3}$/.test(query.get('instance') ?? '') ? `/i/${query.get('instance')}` : '';
const video = document.getElementById('video');
const stateLabel = document.getElementById('state');
const versionLabel = document.getElementById('version');
const statsPanel = document.getElementById('stats');
const warningsPanel = document.getElementById('warnings');
const loading = new LoadingSteps(document.getElementById('loading'));

// What the page knows, also read by the browser tests through window.caustic.
const state = {
  connection: 'connecting', codec: query.get('codec') ?? 'vp8', params: null, version: 0, shownVersion: 0,
  sync: false, poses: new Map(), sentAt: new Map(), shownLog: [], latencies: [], framesShown: 0, shownLevel: 0,
};
window.caustic = state;
// The room's quality: ?quality=high|low, else low on software WebGL, and
// high until the page draws fewer than 30 frames a second.
const forcedQuality = Object.values(Quality).includes(query.get('quality')) ? query.get('quality') : null;
const firstQuality = forcedQuality ?? (softwareWebGL() ? Quality.low : Quality.high);
const frameRate = new FrameRate();
// Settings a shared link carries: sent once, after the first session starts.
let shared = sharedParams(query);

let session = null, stream = null, channel = null, room = null, controls = null, retry = 0;
// Which connect() counts: each call, and each retry, makes the earlier ones stale.
let attempts = 0, cancelRetry = null;
let panel = null, panelParams = null, water = null;  // lil-gui and the object its controllers edit; the pool's water
const panelColour = { glass: 'none' };  // object.glass as the panel's dropdown shows it

function setConnection(name, detail = '') {
  state.connection = name;
  stateLabel.dataset.state = name;
  stateLabel.textContent = detail ? `${name}: ${detail}` : name;
}

// Everything in the scene format a viewer may patch.
function patchable(params) {
  const { mesh, name, description, ...rest } = params;
  const { width, height, ...render } = rest.render;
  return { ...rest, render };
}

// The server's word on settings that show little or nothing, or that
// fidelity "auto" overrides: shown until an answer carries none. The page's
// own (a link's refused settings, a refused drop) come first.
function showWarnings(server = state.serverWarnings ?? []) {
  state.serverWarnings = server;
  const warnings = [state.linkRefused, state.dropRefused, ...server].filter(Boolean);
  state.warnings = warnings;
  warningsPanel.hidden = warnings.length === 0;
  warningsPanel.textContent = warnings.map((w) => `${w.key}: ${w.detail}`).join('\n');
}

function onApplied(body, sentAt) {
  if (!state.params) {
    document.getElementById('title').textContent = body.params.name || sceneId;
    document.title = `${body.params.name || sceneId} – causticd`;
    state.origin = body.params;  // what "changed" is measured against in a shared link
  }
  state.params = body.params;
  state.atlas = body.atlas;
  state.fidelity = body.fidelity;
  showWarnings(body.warnings ?? []);
  if (state.resetting) {
    state.resetting = false;
    refreshPanel(body.params);
    room.apply(body.params, body.atlas);
  }
  rememberAddress();
  state.version = body.version;
  // Latency: from sending the PATCH to the first frame on screen with this
  // version or a later one (the server may skip versions that came in fast).
  const shown = state.shownLog.find(([version]) => version >= body.version);
  if (shown) state.latencies.push(shown[1] - sentAt);
  else state.sentAt.set(body.version, sentAt);
  // What the frame of this version shows: the object's pose and the screen
  // rectangle (which may follow the light), drawn when that frame is shown.
  state.poses.set(body.version, { position: body.params.object.position, rotation_deg: body.params.object.rotation_deg,
                                  screen: body.params.screen, surfaces: body.params, atlas: body.atlas });
  if (state.poses.size > 256) state.poses.delete(state.poses.keys().next().value);
  // The frame may have beaten the answer to the page.
  if (room && state.shownVersion >= body.version) {
    if (state.sync) room.showPose(state.poses.get(body.version));
    room.placeSurfaces(body.params, body.atlas);
  }
}

function onFrameVersion(version, now, level, surface) {
  state.framesShown += 1;
  if (surface) water?.show(surface);  // the water this frame's caustic came from
  if (loading.timer) loading.done();
  state.shownLevel = level;  // 0: full quality, 1: a preview drawn while the scene moves
  if (version === state.shownVersion) return;
  state.shownVersion = version;
  versionLabel.textContent = `frame version ${version}`;
  state.shownLog.push([version, now]);
  if (state.shownLog.length > 256) state.shownLog.shift();
  for (const [pending, sent] of state.sentAt) {
    if (pending > version) continue;
    state.latencies.push(now - sent);
    state.sentAt.delete(pending);
  }
  const pose = state.poses.get(version);
  if (state.sync) room.showPose(pose);
  if (pose) room?.placeSurfaces(pose.surfaces, pose.atlas);
}

// Starts a session and its stream. Only the latest call counts: one that
// a newer call (a codec changed twice, a retry) overtook while the server
// made its session gives that session back at once.
async function connect() {
  const attempt = ++attempts;
  setConnection(retry ? 'reconnecting' : 'connecting');
  loading.begin('session');
  let mine;
  try {
    mine = await createSession(sceneId, state.codec, home);
  } catch (error) {
    if (attempt !== attempts) return;
    if (error instanceof Refused) {
      // Permanent: say what to do instead of asking again forever.
      setConnection('error', `${error.message}. Pick a scene in the gallery.`);
      return;
    }
    const why = error instanceof ServerFull ? error.message
      : error instanceof TypeError ? 'the server does not answer' : error.message;
    setConnection(error instanceof ServerFull ? 'full' : 'reconnecting', why);
    return scheduleRetry(why);
  }
  if (attempt !== attempts) return void deleteSession(mine);
  session = mine;
  try {
    await start(attempt);
  } catch (error) {
    // The page itself failed (the scene's proxy, the room): asking the
    // server again would fail alike, so the session goes back and the page
    // says why.
    if (attempt !== attempts) return;
    console.error(error);
    setConnection('error', `the page could not show this scene: ${error.message}`);
    deleteSession(mine);
    session = null;
  }
}

// The room (the first time), the parameter channel and the stream for the
// session just made.
async function start(attempt) {
  const firstTime = !room;
  if (firstTime) {
    loading.begin('room');
    // One scene by id: a visitor's design is not in the public list. The
    // list, fetched alongside, names the glasses the panel offers.
    const glasses = fetch(`${home}/api/v1/scenes`).then((r) => r.json()).then((j) => j.glasses ?? []).catch(() => []);
    const { proxy, receiver_meshes: shapes } =
      await (await fetch(`${home}/api/v1/scenes/${encodeURIComponent(sceneId)}`)).json();
    state.glasses = await glasses;
    if (attempt !== attempts) return;  // given back by the retry that overtook it
    room = new CausticRoom(document.getElementById('stage'), video, proxy, firstQuality, shapes);
    state.quality = room.quality;
    controls = new ControlModes(room, {
      onLightMoved: () => channel.set({ light: room.lightFromMarker(state.params.light.type) }),
      onObjectMoved: () => channel.set({ object: room.objectPose() }),
      onModeChanged: (mode) => {
        document.getElementById('mode').textContent = `mode: ${mode} (? for keys)`;
        state.mode = mode;
      },
    });
    const onRefused = (problem) => { state.dropRefused = problem; showWarnings(); };
    if (session.params.params.water)
      water = new PoolWater(room, controls, session.params.params.water, { session: () => session, onRefused });
    state.water = water?.record;
  }
  channel = new ParamChannel(session, { onApplied, onError: refused });
  if (state.params) channel.set(patchable(state.params));  // a reconnect keeps what the viewer changed
  else onApplied(session.params, performance.now());
  room.apply(state.params, state.atlas);
  if (firstTime) {
    controls.orbit.target.copy(room.target);
    controls.orbit.update();
    controls.orbit.saveState();  // what "Reset view" returns to
    const view = sharedView(query);
    if (view) {
      room.camera.position.set(view[0], view[1], view[2]);
      controls.orbit.target.set(view[3], view[4], view[5]);
      controls.orbit.update();
    }
    controls.orbit.addEventListener('end', rememberAddress);
    buildGui();
    if (shared) channel.set(shared);
    // The first render compiles every shader: seconds on a slow or loaded
    // machine, during which the page can neither answer the offer nor ping.
    // Done before the stream opens, the server never sees that silence.
    room.render();
  }
  loading.begin('connecting');
  const own = stream = new Stream(session, video, {
    onState: (s, reason) => {
      if (stream !== own) return;  // a stream already replaced
      if (s === 'live') {
        retry = 0;
        setConnection('live');
        if (loading.timer) loading.begin('first frame');
      }
      if (s === 'lost') { setConnection('reconnecting', reason); scheduleRetry(reason); }
    },
    onFrameVersion,
    codec: state.codec.toUpperCase(),
  });
  stream.start();
}

// Tries again after a backoff, counting the seconds down on the page. The
// session, its stream and its channel end here; a retry already waiting,
// or a connect() still asking the server, gives way to this one.
function scheduleRetry(why = '') {
  // A closed signalling socket ends the session on the server already: a
  // DELETE would only be refused. Otherwise the DELETE goes first: closing
  // the socket first would end the session under it.
  const [old, oldStream] = [session, stream];
  oldStream?.mute();
  const release = old && !oldStream?.socketClosed ? deleteSession(old) : Promise.resolve();
  release.finally(() => oldStream?.close());
  channel?.close();
  session = null;
  stream = null;
  attempts += 1;
  cancelRetry?.();
  cancelRetry = retryAfter(retry++, (left) => {
    if (why) setConnection(state.connection, `${why}; retrying in ${left} s`);
  }, connect);
}

// A refused patch: the settings of a shared link are said to be refused
// (and leave the address), anything else goes to the console.
function refused(problem) {
  if (!shared) return console.warn('patch refused:', problem.detail);
  shared = null;
  state.linkRefused = { key: problem.key ?? 'link', detail: `the link's settings were refused: ${problem.detail}` };
  showWarnings();
  rememberAddress();
}

// The address bar always holds a link to what is on screen (share.js).
function rememberAddress() {
  if (!state.origin || !state.params || !room) return;
  if (shared && state.version > 1) shared = null;  // the link's settings are in
  state.address = writeAddress({ patch: changedParams(state.origin, state.params), camera: room.camera.position,
                                 target: controls.orbit.target, codec: state.codec });
}

document.getElementById('share').addEventListener('click', async () => {
  rememberAddress();
  const button = document.getElementById('share');
  try {
    await navigator.clipboard.writeText(location.href);
    button.textContent = 'Link copied';
  } catch {
    window.prompt('Copy this link', location.href);  // no clipboard outside a secure context
  }
  setTimeout(() => { button.textContent = 'Share'; }, 2000);
});

// Every section back to the scene's own values: a null in a patch restores
// them on the server (docs/api.md); its answer then refreshes the panel.
function resetScene() {
  state.resetting = true;
  channel.set({ object: null, light: null, screen: null, render: null, post: null, ...(water && { water: null }) });
}

// The panel's name for object.glass: a catalogue name, "none", or "custom"
// for coefficients (shown, not offered).
const glassName = (glass) => (glass === null || glass === undefined ? 'none' : typeof glass === 'string' ? glass : 'custom');

function refreshPanel(params) {
  for (const section of ['object', 'light', 'screen', 'render', 'post', 'water'])
    if (params[section]) Object.assign(panelParams[section], params[section]);
  panelColour.glass = glassName(params.object.glass);
  panel.controllersRecursive().forEach((c) => c.updateDisplay());
}

function buildGui() {
  const gui = new GUI({ title: 'Caustic' });
  // A phone's screen is the picture's: the panel starts folded there.
  if (matchMedia('(max-width: 720px)').matches) gui.close();
  const p = state.params;
  panel = gui;
  panelParams = p;
  gui.add({ resetView: () => controls.orbit.reset() }, 'resetView').name('Reset view');
  gui.add({ resetScene }, 'resetScene').name('Reset scene');
  const send = (section, key) => (value) => channel.set({ [section]: { [key]: value } });
  const material = gui.addFolder('Material');
  material.add(p.object, 'material', ['refractive', 'reflective']).onChange(send('object', 'material'));
  material.add(p.object, 'ior', 1.0, 3.0, 0.01).onChange(send('object', 'ior'));
  // A glass disperses: the frame turns to colour, one pass per wavelength.
  // "none" (not null, which would restore the scene's own glass) removes it.
  panelColour.glass = glassName(p.object.glass);
  const glasses = ['none', ...(state.glasses ?? [])];
  if (!glasses.includes(panelColour.glass)) glasses.push(panelColour.glass);
  material.add(panelColour, 'glass', glasses).name('glass (dispersion)').onChange((glass) => {
    if (glass !== 'custom') channel.set({ object: { glass } });
  });
  const light = gui.addFolder('Light');
  light.add(p.light, 'type', ['directional', 'point']).onChange((type) => {
    channel.set({ light: { type, ...room.lightFromMarker(type) } });
  });
  light.add(p.light, 'spectrum', ['d65', 'e', 'blackbody', 'led']).name('spectrum (with a glass)')
    .onChange(send('light', 'spectrum'));
  light.add(p.light, 'temperature_k', 1000, 40000, 100).name('blackbody (K)').onChange(send('light', 'temperature_k'));
  const quality = gui.addFolder('Quality');
  quality.add(p.render, 'fidelity', ['auto', 'manual']).onChange(send('render', 'fidelity'));
  quality.add(p.render, 'accuracy_target', 0.001, 0.2, 0.001).name('target L1 (auto)').onChange(send('render', 'accuracy_target'));
  quality.add(p.render, 'mesh_resolution', state.fidelity.levels).name('mesh level (manual)')
    .onChange((n) => channel.set({ render: { mesh_resolution: Number(n) } }));
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
  if (water && p.water) water.addFolder(gui, p.water, (key) => send('water', key));
  const view = gui.addFolder('Stream');
  view.add(state, 'codec', ['vp8', 'h264']).onChange(() => {
    // The address keeps the choice: a reload or a shared link streams the same codec.
    rememberAddress();
    retry = 1;
    scheduleRetry();
  });
  view.add(state, 'sync').name('synchronous pose');
  view.add(state, 'quality', Object.values(Quality)).name('room quality').onChange((q) => room.setQuality(q)).listen();
  view.add({ stats: false }, 'stats').name('stats overlay').onChange((on) => { statsPanel.hidden = !on; });
}

showStats(statsPanel, () => stream?.pc, state);

// Help (?) and fullscreen (F): buttons for pointers and touch, keys for keyboards.
const helpPanel = document.getElementById('help');
const toggleHelp = () => { helpPanel.hidden = !helpPanel.hidden; };
const toggleFullscreen = () => {
  if (document.fullscreenElement) document.exitFullscreen().catch(() => {});
  else document.documentElement.requestFullscreen?.().catch(() => {});
};
document.getElementById('help-button').addEventListener('click', toggleHelp);
document.getElementById('fullscreen').addEventListener('click', toggleFullscreen);
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;  // typing in the panel
  if (e.key === '?') toggleHelp();
  if (e.key === 'f' || e.key === 'F') toggleFullscreen();
});

installTestHooks(state, () => ({ room, controls, channel, stream, session, resetScene, water, loading }));

window.addEventListener('pagehide', () => { if (session) deleteSession(session); });

function frame(now) {
  requestAnimationFrame(frame);
  if (!room) return;
  const fps = frameRate.tick(now);
  if (fps !== null) {
    state.fps = fps;
    // Too slow for the transmissive glass and soft shadows: the cheaper room, once.
    if (!forcedQuality && fps < 30 && room.quality === Quality.high) {
      room.setQuality(Quality.low);
      state.quality = Quality.low;
      state.qualityChosenAt = fps;
    }
  }
  if (!state.sync) room.followHandle();
  if (state.params && controls?.mode !== 'light') room.placeLight(state.params.light);
  room.render();
}
requestAnimationFrame(frame);
connect();
