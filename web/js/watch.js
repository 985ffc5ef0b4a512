// SPDX-License-Identifier: LGPL-2.1-or-later
// The page of a broadcast's viewer link (POST .../viewers answers it): the
// link's fragment holds the broadcast server's address, the mountpoint, its
// pin and a short-lived token; the page plays the stream and says which
// parameter version it shows. Its holder drives the scene; viewers watch.
import { JanusStream } from './janus_stream.js';

const link = new URLSearchParams(location.hash.slice(1));
const stateLabel = document.getElementById('state');
const versionLabel = document.getElementById('version');
const video = document.getElementById('video');

// What the page knows, also read by the browser tests through window.caustic.
// connectedAt and firstFrameAt (performance.now()) say how long a late
// joiner waited for its first picture.
const state = { connection: 'connecting', version: 0, level: 0, error: '', connectedAt: 0, firstFrameAt: 0 };
window.caustic = state;

function setConnection(connection, why = '') {
  if (connection === 'live' && !state.connectedAt) state.connectedAt = performance.now();
  state.connection = connection;
  state.error = why;
  stateLabel.dataset.state = connection;
  stateLabel.textContent = why ? `${connection}: ${why}` : connection;
}

async function title() {
  const scene = link.get('scene');
  if (!scene || !/^[a-z0-9_-]{1,64}$/.test(scene)) return;
  const response = await fetch(`/api/v1/scenes/${scene}`).catch(() => null);
  if (!response?.ok) return;
  const { name } = await response.json();
  document.getElementById('title').textContent = name;
  document.title = `${name} (broadcast)`;
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
});
state.peer = () => stream.pc;
state.stream = stream;
if ('requestVideoFrameCallback' in video) {
  video.requestVideoFrameCallback((now) => { state.firstFrameAt = now; });
}
title();
stream.start().catch((error) => setConnection('error', error.message));
addEventListener('pagehide', () => stream.close());
