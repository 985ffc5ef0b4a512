// SPDX-License-Identifier: LGPL-2.1-or-later
// The page of a broadcast's viewer link (POST .../viewers answers it): the
// link's fragment holds the broadcast server's address, the mountpoint, its
// pin and a short-lived token; the page plays the stream in the same room
// as the viewer (the scene's public slab, screen and light, placed by the
// parameters the stream's data carries) and says which parameter version
// it shows. Its holder drives the scene; viewers watch and look around.
// `view=video` in the fragment shows the plain video instead (a device
// without WebGL, or a wall display).
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { JanusStream } from './janus_stream.js';
import { FrameRate, Quality, softwareWebGL } from './room.js';
import { CausticRoom } from './scene3d.js';

const link = new URLSearchParams(location.hash.slice(1));
const stateLabel = document.getElementById('state');
const versionLabel = document.getElementById('version');
const video = document.getElementById('video');
const flat = link.get('view') === 'video';
video.hidden = !flat;  // in the room it is the lightmap's texture
const toggle = document.getElementById('view-toggle');
toggle.textContent = flat ? '3D room' : 'video only';
toggle.addEventListener('click', (event) => {
  event.preventDefault();
  const next = new URLSearchParams(link);
  if (flat) next.delete('view');
  else next.set('view', 'video');
  location.hash = next.toString();
  location.reload();  // the same link's other view: a fresh page
});

// What the page knows, also read by the browser tests through window.caustic.
// connectedAt and firstFrameAt (performance.now()) say how long a late
// joiner waited for its first picture; params is what placed the room.
const state = { connection: 'connecting', version: 0, level: 0, error: '', connectedAt: 0, firstFrameAt: 0,
                params: null, paramsVersion: 0, view: flat ? 'video' : 'room', fps: 0 };
window.caustic = state;

function setConnection(connection, why = '') {
  if (connection === 'live' && !state.connectedAt) state.connectedAt = performance.now();
  state.connection = connection;
  state.error = why;
  stateLabel.dataset.state = connection;
  stateLabel.textContent = why ? `${connection}: ${why}` : connection;
}

const sceneId = link.get('scene');
const validScene = sceneId && /^[a-z0-9_-]{1,64}$/.test(sceneId);
// The scene's public description: its name, and the slab that stands in
// for the object (never the real mesh).
const described = validScene
  ? fetch(`/api/v1/scenes/${sceneId}`).then((r) => (r.ok ? r.json() : null)).catch(() => null)
  : Promise.resolve(null);
described.then((scene) => {
  if (!scene) return;
  document.getElementById('title').textContent = scene.name;
  document.title = `${scene.name} (broadcast)`;
});

let room = null, orbit = null;
async function placeRoom(params, version) {
  if (version < state.paramsVersion) return;  // an older message, overtaken
  state.params = params;
  state.paramsVersion = version;
  if (flat) return;
  if (!room) {
    const scene = await described;
    if (!scene?.proxy || room) return;
    room = new CausticRoom(document.getElementById('stage'), video, scene.proxy,
                           softwareWebGL() ? Quality.low : Quality.high);
    room.apply(state.params);  // frames the first view
    orbit = new OrbitControls(room.camera, room.renderer.domElement);
    orbit.target.copy(room.target);
    orbit.update();
    return;
  }
  room.apply(state.params);
}

const stream = new JanusStream({
  url: new URL(link.get('janus') ?? '', location.href).href.replace(/^http/, 'ws'),
  mountpoint: Number(link.get('mountpoint')),
  pin: link.get('pin') ?? '',
  token: link.get('token') ?? '',
}, video, {
  onState: setConnection,
  onVersion: (version, level) => {
    state.version = version;
    state.level = level;
    versionLabel.textContent = `frame version ${version}${level ? ' (preview)' : ''}`;
  },
  onParams: (params, version) => { placeRoom(params, version); },
});
state.peer = () => stream.pc;
state.stream = stream;
state.room = () => room;
if ('requestVideoFrameCallback' in video) {
  video.requestVideoFrameCallback((now) => { state.firstFrameAt = now; });
}
stream.start().catch((error) => setConnection('error', error.message));
addEventListener('pagehide', () => stream.close());

const frameRate = new FrameRate();
function frame(now) {
  requestAnimationFrame(frame);
  if (!room) return;
  const fps = frameRate.tick(now);
  if (fps !== null) state.fps = fps;
  room.followHandle();
  room.render();
}
requestAnimationFrame(frame);
