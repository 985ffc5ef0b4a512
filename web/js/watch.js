// SPDX-License-Identifier: LGPL-2.1-or-later
// The page of a broadcast's viewer link (POST .../viewers answers it): the
// link's fragment holds the broadcast server's address, the mountpoint, its
// pin and a short-lived token; the page plays the stream in the same room
// as the viewer (the scene's public slab, screen and light, placed by the
// parameters the stream's data carries) and says which parameter version
// it shows. Its holder drives the scene; viewers watch and look around.
// A pool's surface is drawn from the heights of the frame being shown
// (water.js), as in the viewer; a viewer of a broadcast drops no stones.
// `view=video` in the fragment shows the plain video instead (a device
// without WebGL, or a wall display).
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { JanusStream } from './janus_stream.js';
import { FrameRate } from './frame_rate.js';
import { installViewKeys } from './keyboard_view.js';
import { retryAfter, retryDelay, transient } from './retry.js';
import { Quality, softwareWebGL } from './room.js';
import { CausticRoom } from './scene3d.js';
import { showState } from './state_label.js';
import { missingSupport } from './support.js';
import { ShownWater } from './water.js';
import { installWatchTestHooks } from './watch_test_hooks.js';

const link = new URLSearchParams(location.hash.slice(1));
const stateLabel = document.getElementById('state');
const versionLabel = document.getElementById('version');
const video = document.getElementById('video');
let flat = link.get('view') === 'video';  // also when the room cannot be drawn
video.hidden = !flat;  // in the room it is the lightmap's texture
const toggle = document.getElementById('view-toggle');
toggle.textContent = flat ? '3D room' : 'video only';
// Tries of the scene's description (the room needs it) before the page
// settles for the plain video.
const DESCRIBE_TRIES = 5;
// The backoff starts over once the pictures have been on screen this long:
// a stream that dies as it starts is not asked for again at the first pace.
const STEADY_MS = 5000;
// A button, not a link: it reloads the page in the other view (a link to
// the same page but its fragment would not load it again).
toggle.addEventListener('click', () => {
  const next = new URLSearchParams(link);
  if (flat) next.delete('view');
  else next.set('view', 'video');
  location.hash = next.toString();
  location.reload();  // the same link's other view: a fresh page
});

// What the page knows, also read by the browser tests through window.caustic;
// params is what placed the room.
const state = { connection: 'connecting', version: 0, level: 0, error: '', params: null, paramsVersion: 0,
                view: flat ? 'video' : 'room', fps: 0 };
window.caustic = state;

function setConnection(connection, why = '', countdown = '') {
  state.connection = connection;
  state.error = countdown ? `${why}; ${countdown}` : why;
  showState(stateLabel, connection, why, countdown);
}

const sceneId = link.get('scene');
const validScene = sceneId && /^[a-z0-9_-]{1,64}$/.test(sceneId);
// The scene's public description: its name, and the slab that stands in
// for the object (never the real mesh).
async function describe() {
  for (let attempt = 0; validScene; ++attempt) {
    try {
      const response = await fetch(`/api/v1/scenes/${sceneId}`);
      if (response.ok) return await response.json();
      if (!transient(response.status)) return null;  // no such scene
    } catch {
      // No answer (the server restarting, a network blip): asked again below.
    }
    if (attempt + 1 >= DESCRIBE_TRIES) return null;
    await new Promise((resolve) => { setTimeout(resolve, retryDelay(attempt)); });
  }
  return null;
}
const described = describe();
described.then((scene) => {
  if (!scene) return;
  document.getElementById('title').textContent = scene.name;
  document.title = `${scene.name} (broadcast)`;
});

// Receivers come one message each after their version's room message.
// Until a version's are all in, the last complete set stands if it has as
// many; with none, the whole picture is the screen's lightmap.
const receivers = { version: -1, list: [], shown: null };
function takeReceiver(receiver, version) {
  if (version < receivers.version || !(receiver.count >= 1 && receiver.count <= 16)) return;
  if (version > receivers.version) Object.assign(receivers, { version, list: new Array(receiver.count).fill(null) });
  if (receiver.count !== receivers.list.length || !(receiver.index >= 0 && receiver.index < receiver.count)) return;
  receivers.list[receiver.index] = receiver;
  if (receivers.list.every(Boolean)) {
    receivers.shown = receivers.list;
    if (state.params) placeRoom(state.params, state.paramsVersion);
  }
}

// The room's params with their receivers, and the atlas that cuts the
// picture onto the surfaces.
function surfaces(params) {
  const set = receivers.shown;
  if (!params.receiver_count || set?.length !== params.receiver_count || !params.render || !params.tile) {
    return { params: { ...params, receivers: [], render: { width: 1, height: 1 } }, atlas: null };
  }
  return { params: { ...params, receivers: set.map((r) => r.surface) }, atlas: [params.tile, ...set.map((r) => r.tile)] };
}

// Without a room (no WebGL, no description of the scene) the broadcast
// is still worth watching: the page shows its plain video instead.
function showVideoOnly(why) {
  if (flat) return;
  console.warn(`the broadcast is shown as plain video: ${why}`);
  flat = true;
  state.view = 'video';
  state.viewError = why;
  document.getElementById('stage').replaceChildren();
  video.hidden = false;
  toggle.textContent = '3D room';
}

let room = null, orbit = null, water = null, waited = 0;
async function placeRoom(params, version) {
  if (version < state.paramsVersion) return;  // an older message, overtaken
  state.params = params;
  state.paramsVersion = version;
  if (flat) return;
  if (!room) {
    // The first view frames every surface: wait for the receivers, but
    // not beyond the next room message (one a second) if one went missing.
    if (params.receiver_count && surfaces(params).atlas === null && (waited += 1) <= 2) return;
    const scene = await described;
    if (room || flat) return;
    if (!scene?.proxy) return showVideoOnly('the scene\'s description did not come');
    room = new CausticRoom(document.getElementById('stage'), video, scene.proxy,
                           softwareWebGL() ? Quality.low : Quality.high, scene.receiver_meshes);
    frameRate.reset();
    const { params: placed, atlas } = surfaces(state.params);
    room.apply(placed, atlas);  // frames the first view
    orbit = new OrbitControls(room.camera, room.renderer.domElement);
    orbit.target.copy(room.target);
    orbit.update();
    installViewKeys({ mode: 'none', orbit }, {});  // arrows turn, + and - zoom, as in the viewer
    frames.watch();
  } else {
    const { params: placed, atlas } = surfaces(state.params);
    room.apply(placed, atlas);
  }
  // A pool: its surface in place of the slab, at the size the room message names.
  if (state.params.water && !water) {
    water = new ShownWater(room, state.params.water);
    state.water = water.record;
  }
}

// Which frame message each shown frame came with. Janus numbers a viewer's
// RTP timestamps from the first packet it relays to that viewer, so a shown
// frame's timestamp is the server's (the message's) less an offset of this
// page's own, learnt from the recently shown frames: of the offsets that
// pair at least half of them with messages, the one whose messages arrived
// nearest the times their frames did (they leave the server together;
// steady frame intervals pair shifted offsets too). While the offset in use
// pairs half of them, a frame without a message by it (late or lost) shows
// none rather than another frame's.
const MESSAGES_KEPT = 512;
const FRAMES_PAIRED = 16;
const PAIRED_TO_LEARN = 3;
const ARRIVALS_APART_MS = 1000;  // at most, between a frame and its message
class FrameMessages {
  constructor(video, onShown) {
    Object.assign(this, { video, onShown, offset: null, shown: [], paired: 0 });
    this.messages = new Map();  // the server's rtp timestamp -> { message, at (arrival, ms) }
  }

  add(message) {
    if (!Number.isInteger(message.rtp_timestamp)) return;
    this.messages.set(message.rtp_timestamp >>> 0, { message, at: performance.now() });
    if (this.messages.size > MESSAGES_KEPT) this.messages.delete(this.messages.keys().next().value);
  }

  // The recent frames `offset` pairs with messages: how many, and how far
  // apart their arrivals were on average (ms).
  pairing(offset) {
    let count = 0, apart = 0;
    for (const { rtp, at } of this.shown) {
      const told = this.messages.get((rtp + offset) >>> 0);
      if (told) [count, apart] = [count + 1, apart + Math.abs(told.at - at)];
    }
    return { count, apart: count ? apart / count : Infinity };
  }

  // The message of a shown frame (its timestamp, and when it arrived), or undefined.
  match(rtp, at) {
    this.shown.push({ rtp, at });
    if (this.shown.length > FRAMES_PAIRED) this.shown.shift();
    const told = (offset) => this.messages.get((rtp + offset) >>> 0)?.message;
    const enough = Math.max(PAIRED_TO_LEARN, this.shown.length / 2);
    if (this.offset !== null && !told(this.offset) && this.pairing(this.offset).count >= enough) return undefined;
    let best = null, nearest = Infinity;
    for (const [key, message] of this.messages) {
      if (Math.abs(message.at - at) > ARRIVALS_APART_MS) continue;
      const offset = (key - rtp) >>> 0;  // one that pairs this frame
      const { count, apart } = this.pairing(offset);
      if (count >= enough && apart < nearest) [best, nearest] = [offset, apart];
    }
    if (best !== null) this.offset = best;
    return this.offset === null ? undefined : told(this.offset);
  }

  watch() {
    if (!('requestVideoFrameCallback' in this.video)) return;
    const onFrame = (now, meta) => {
      const message = this.match(meta.rtpTimestamp, meta.receiveTime ?? now);
      if (message) {
        this.paired += 1;
        this.onShown(message);
      }
      this.video.requestVideoFrameCallback(onFrame);
    };
    this.video.requestVideoFrameCallback(onFrame);
  }
}
const frames = new FrameMessages(video, (message) => water?.show(message.water));

const broadcast = {
  url: new URL(link.get('janus') ?? '', location.href).href.replace(/^http/, 'ws'),
  mountpoint: Number(link.get('mountpoint')),
  pin: link.get('pin') ?? '',
  token: link.get('token') ?? '',
};
let stream = null;
let retry = 0;
const frameRate = new FrameRate();

// Watches the broadcast; a lost connection, a server that does not answer
// or a mountpoint not there yet (Janus restarted, the server making it
// again) is tried again after a backoff, a refused link is not.
function watch() {
  const missing = missingSupport({ room: false });  // without WebGL the page shows the plain video
  if (missing) return setConnection('error', missing);
  const mine = stream = new JanusStream(broadcast, video, {
    onState: (s, why) => {
      if (stream !== mine) return;
      if (s === 'live') resetRetryWhenSteady(mine);
      if (s === 'lost') scheduleRetry(why);
      else setConnection(s, why);
    },
    onVersion: (version, level) => {
      state.version = version;
      state.level = level;
      versionLabel.textContent = `frame version ${version}${level ? ' (preview)' : ''}`;
    },
    onParams: (params, version) => {
      placeRoom(params, version).catch((error) => {
        room = null;
        showVideoOnly(`the 3D room could not be drawn (${error.message})`);
      });
    },
    onReceiver: takeReceiver,
    onFrame: (message) => { if (!flat && message.water) frames.add(message); },  // a pool's
  });
  stream.start().catch((error) => {
    if (stream !== mine || mine.closed) return;  // lost already, and being tried again
    mine.close();
    if (error.transient) scheduleRetry(error.message);
    else setConnection('error', error.message);
  });
}

function resetRetryWhenSteady(mine) {
  const steady = () => setTimeout(() => { if (stream === mine && !mine.closed) retry = 0; }, STEADY_MS);
  if ('requestVideoFrameCallback' in video) video.requestVideoFrameCallback(steady);
  else steady();
}

function scheduleRetry(why) {
  retryAfter(retry++, (left) => setConnection('reconnecting', why, `retrying in ${left} s`), watch);
}

watch();
addEventListener('pagehide', () => stream?.close());

function frame(now) {
  requestAnimationFrame(frame);
  if (!room) return;
  const fps = frameRate.tick(now);
  if (fps !== null) state.fps = fps;
  room.followHandle();
  room.render();
}
requestAnimationFrame(frame);
// A hidden tab draws nothing: that time is not the page's frame rate.
document.addEventListener('visibilitychange', () => { if (!document.hidden) frameRate.reset(); });

installWatchTestHooks(state, () => ({ room, stream, water, receivers, frames }));
