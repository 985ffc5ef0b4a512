// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer: starts a session for ?scene=ID&codec=vp8|h264, shows the
// streamed caustic on the lightmap plane (and a pool's water, water.js), and
// turns the controls into coalesced parameter patches.
import { createSession, deleteSession, getParams, ParamChannel, Refused, ServerFull } from './api.js';
import { ControlModes } from './controls.js';
import { FrameRate } from './frame_rate.js';
import { followHeaderHeight } from './header_height.js';
import { installHelpAndFullscreen } from './help.js';
import { LoadingSteps } from './loading.js';
import { Panel } from './panel.js';
import { retryAfter } from './retry.js';
import { Quality, softwareWebGL } from './room.js';
import { CausticRoom } from './scene3d.js';
import { changedParams, sharedParams, sharedView, writeAddress } from './share.js';
import { installShareButton } from './share_button.js';
import { showState } from './state_label.js';
import { showStats } from './stats_overlay.js';
import { Stream } from './stream.js';
import { missingSupport } from './support.js';
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

const CODECS = ['vp8', 'h264'];
const askedCodec = query.get('codec') ?? 'vp8';
// What the page knows, also read by the browser tests through window.caustic.
const state = {
  connection: 'connecting', codec: CODECS.includes(askedCodec) ? askedCodec : 'vp8', params: null, version: 0,
  shownVersion: 0, sync: false, poses: new Map(), sentAt: new Map(), shownLog: [], latencies: [], framesShown: 0,
  shownLevel: 0,
};
if (state.codec !== askedCodec)
  state.codecRefused = { key: 'codec', detail: `"${askedCodec}" is not one of ${CODECS.join(', ')}: streaming vp8` };
window.caustic = state;
// PATCH-to-screen latencies (the stats overlay's median): the recent ones.
const LATENCIES_KEPT = 256;
// A stream that dies soon after it starts (a server that ends it at once)
// must not be retried at the first step's pace for ever: the backoff
// starts over only once its pictures have been on screen this long.
const STEADY_MS = 5000;
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
let panel = null, water = null;

function setConnection(name, detail = '', countdown = '') {
  state.connection = name;
  state.why = detail;
  showState(stateLabel, name, detail, countdown);
  if (name === 'error') loading.stop();  // nothing more is on its way
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
  const warnings = [state.codecRefused, state.linkRefused, state.dropRefused, state.patchRefused, ...server].filter(Boolean);
  state.warnings = warnings;
  warningsPanel.hidden = warnings.length === 0;
  const text = warnings.map((w) => `${w.key}: ${w.detail}`).join('\n');
  if (warningsPanel.textContent !== text) warningsPanel.textContent = text;  // a live region: read when it changes
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
    panel.refresh(body.params);
    room.apply(body.params, body.atlas);
  }
  rememberAddress();
  state.version = body.version;
  // Latency: from sending the PATCH to the first frame on screen with this
  // version or a later one (the server may skip versions that came in fast).
  // (An answer read back from the server, sentAt null, was sent by no one.)
  const shown = state.shownLog.find(([version]) => version >= body.version);
  if (sentAt !== null && shown) noteLatency(shown[1] - sentAt);
  else if (sentAt !== null) state.sentAt.set(body.version, sentAt);
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
    noteLatency(now - sent);
    state.sentAt.delete(pending);
  }
  const pose = state.poses.get(version);
  if (state.sync) room.showPose(pose);
  if (pose) room?.placeSurfaces(pose.surfaces, pose.atlas);
}

function noteLatency(ms) {
  state.latencies.push(ms);
  if (state.latencies.length > LATENCIES_KEPT) state.latencies.shift();
}

// Starts a session and its stream. Only the latest call counts: one that
// a newer call (a codec changed twice, a retry) overtook while the server
// made its session gives that session back at once.
async function connect() {
  const missing = missingSupport();
  if (missing) return setConnection('error', missing);
  const attempt = ++attempts;
  // A retry after a failure keeps the line's words (a screen reader read
  // the state and its reason once); only the part it is not read says so.
  const waiting = state.why && ['reconnecting', 'full'].includes(state.connection);
  if (retry && waiting) setConnection(state.connection, state.why, 'trying again now');
  else setConnection(retry ? 'reconnecting' : 'connecting');
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
    return scheduleRetry(why, error.retryAfterMs);
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
    const described = await fetch(`${home}/api/v1/scenes/${encodeURIComponent(sceneId)}`);
    if (!described.ok) throw new Error(`the scene's description: the server answered ${described.status}`);
    const { proxy, receiver_meshes: shapes } = await described.json();
    state.glasses = await glasses;
    if (attempt !== attempts) return;  // given back by the retry that overtook it
    room = new CausticRoom(document.getElementById('stage'), video, proxy, firstQuality, shapes);
    frameRate.reset();  // the load drew nothing: it is not the room's frame rate
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
  channel = new ParamChannel(session, {
    onApplied: (body, sentAt) => {
      state.patchRefused = null;
      onApplied(body, sentAt);
    },
    onError: refused,
    onRetrying: (problem, ms) => patchWarning(`${problem.detail}; sending it again in ${Math.ceil(ms / 1000)} s`),
    onGaveUp: (problem) => {
      patchWarning(`${problem.detail}; the change was given up and the panel shows the server's settings`);
      resync();
    },
  });
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
    panel = new Panel(state, {
      channel: () => channel, room: () => room, controls: () => controls, water: () => water, resetScene, statsPanel,
      onCodec: () => {
        // The address keeps the choice: a reload or a shared link streams the same codec.
        rememberAddress();
        retry = 1;
        scheduleRetry();
      },
    });
    if (shared) channel.set(shared);
    // The first render compiles every shader: seconds on a slow or loaded
    // machine, during which the page can neither answer the offer nor ping.
    // Done before the stream opens, the server never sees that silence.
    room.render();
  }
  loading.begin('connecting');
  let steady = null;
  const own = stream = new Stream(session, video, {
    onState: (s, reason) => {
      if (stream !== own) return;  // a stream already replaced
      if (s === 'live') {
        setConnection('live');
        if (loading.timer) loading.begin('first frame');
      }
      if (s === 'lost') {
        clearTimeout(steady);
        setConnection('reconnecting', reason);
        scheduleRetry(reason);
      }
    },
    onFrameVersion: (...shown) => {
      steady ??= setTimeout(() => { if (stream === own) retry = 0; }, STEADY_MS);
      onFrameVersion(...shown);
    },
    codec: state.codec.toUpperCase(),
  });
  stream.start();
}

// Tries again after a backoff, counting the seconds down on the page. The
// session, its stream and its channel end here; a retry already waiting,
// or a connect() still asking the server, gives way to this one.
function scheduleRetry(why = '', serverMs = null) {
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
    if (why) setConnection(state.connection, why, `retrying in ${left} s`);
  }, connect, serverMs);
}

// A refused patch: the settings of a shared link are said to be refused
// (and leave the address), anything else goes to the console; either way
// the panel goes back to what the server holds.
function refused(problem) {
  resync();
  if (!shared) return console.warn('patch refused:', problem.detail);
  shared = null;
  state.linkRefused = { key: problem.key ?? 'link', detail: `the link's settings were refused: ${problem.detail}` };
  showWarnings();
  rememberAddress();
}

// A patch the server did not take (yet): said under the header until one is taken.
function patchWarning(detail) {
  state.patchRefused = { key: 'settings', detail };
  showWarnings();
}

// The panel and the room back to the server's settings, where the page's
// own did not reach it.
async function resync() {
  const mine = session;
  const body = await getParams(mine).catch(() => null);
  if (!body || session !== mine || body.version < state.version) return;
  state.resetting = true;  // as after "Reset scene": the answer sets the panel and the room
  onApplied(body, null);
}

// The address bar always holds a link to what is on screen (share.js).
function rememberAddress() {
  if (!state.origin || !state.params || !room) return;
  if (shared && state.version > 1) shared = null;  // the link's settings are in
  state.address = writeAddress({ patch: changedParams(state.origin, state.params), camera: room.camera.position,
                                 target: controls.orbit.target, codec: state.codec });
}

installShareButton(() => {
  rememberAddress();
  return location.href;
});

// Every section back to the scene's own values: a null in a patch restores
// them on the server (docs/api.md); its answer then refreshes the panel.
function resetScene() {
  state.resetting = true;
  channel.set({ object: null, light: null, screen: null, render: null, post: null, ...(water && { water: null }) });
}

showStats(statsPanel, () => stream?.pc, state);

followHeaderHeight();
installHelpAndFullscreen();

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
    }
  }
  if (!state.sync) room.followHandle();
  if (state.params && controls?.mode !== 'light') room.placeLight(state.params.light);
  room.render();
}
requestAnimationFrame(frame);
// A hidden tab draws nothing: that time is not the room's frame rate.
document.addEventListener('visibilitychange', () => { if (!document.hidden) frameRate.reset(); });
connect();
