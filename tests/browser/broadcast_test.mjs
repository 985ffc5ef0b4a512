// SPDX-License-Identifier: LGPL-2.1-or-later
// A broadcast through Janus to several headless Chromium viewers: they all
// decode what the server sends, a late joiner gets its first frame at once
// (Janus keeps the last key frame), the holder's PATCH reaches every viewer,
// and after a Janus restart the mountpoint is back and viewers rejoin.
// Run by tests/janus/broadcast_test.sh inside a network namespace (Janus
// needs a non-loopback interface for ICE: JANUS_ICE_INTERFACE). Every wait
// is bounded.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdirSync, mkdtempSync, openSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchChromium } from './chromium.mjs';
import { shots, startServer, until } from './harness.mjs';

const VIEWERS = 4;
const secrets = { admin: 'bc-admin-secret-0123456', key: 'bc-streaming-key-012345', token: 'bc-token-secret-0123456' };
const dir = mkdtempSync('/tmp/causticd-janus-');
let browser, server, janus, ports;

const freePort = () => new Promise((resolve) => {
  const s = net.createServer().listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
});

// The shipped configuration (janus/), with this test's ports and secrets.
function writeJanusConfig() {
  for (const name of readdirSync(process.env.CAUSTIC_JANUS_DIR)) {
    let text = readFileSync(path.join(process.env.CAUSTIC_JANUS_DIR, name), 'utf8')
      .replaceAll('/etc/causticd/janus', dir).replaceAll('@JANUS_ADMIN_SECRET@', secrets.admin)
      .replaceAll('@JANUS_TOKEN_SECRET@', secrets.token).replaceAll('@JANUS_STREAMING_KEY@', secrets.key)
      .replace('admin_port = 7088', `admin_port = ${ports.admin}`).replace('ws_port = 8188', `ws_port = ${ports.ws}`);
    writeFileSync(path.join(dir, name), text);
  }
}

async function startJanus() {
  janus = spawn('janus', ['-F', dir, '-C', `${dir}/janus.jcfg`, '-o', '-d', '3', '-E', process.env.JANUS_ICE_INTERFACE],
                { stdio: ['ignore', openSync(`${dir}/janus.log`, 'a'), openSync(`${dir}/janus.log`, 'a')] });
  for (let i = 0; i < 100; i += 1) {
    const up = await new Promise((resolve) => {
      const c = net.connect(ports.ws, '127.0.0.1', () => { c.destroy(); resolve(true); }).on('error', () => resolve(false));
    });
    if (up) return;
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error('janus did not start');
}

const stopJanus = () => new Promise((resolve) => { janus.once('exit', resolve); janus.kill('SIGTERM'); });

async function api(method, url, body, token) {
  const response = await fetch(`${server.url}${url}`, {
    method, headers: { 'Content-Type': 'application/json', ...(token ? { Authorization: `Bearer ${token}` } : {}) },
    body: body ? JSON.stringify(body) : undefined,
  });
  return { status: response.status, body: response.status === 204 ? null : await response.json() };
}

async function sentFrames() {
  const text = await (await fetch(`${server.url}/metrics`)).text();
  return Number(/causticd_frames_sent_total (\d+)/.exec(text)[1]);
}

const videoStat = (name) => window.caustic.peer()?.getStats().then((report) => {
  let n = 0;
  report.forEach((r) => { if (r.type === 'inbound-rtp' && r.kind === 'video') n = r[name]; });
  return n;
});
// Passed to the page whole: no reference to videoStat.
const framesDecoded = () => window.caustic.peer()?.getStats().then((report) => {
  let n = 0;
  report.forEach((r) => { if (r.type === 'inbound-rtp' && r.kind === 'video') n = r.framesDecoded; });
  return n;
});

before(async () => {
  ports = { admin: await freePort(), ws: await freePort() };
  writeJanusConfig();
  await startJanus();
  server = await startServer(['--set', `janus_admin_url=http://127.0.0.1:${ports.admin}/admin`,
                              '--set', `janus_admin_secret=${secrets.admin}`, '--set', `janus_streaming_key=${secrets.key}`,
                              '--set', `janus_token_secret=${secrets.token}`,
                              '--set', `janus_ws_url=ws://127.0.0.1:${ports.ws}/`, '--set', 'drain_timeout_s=0']);
  browser = await launchChromium();
});
after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
  if (janus) await stopJanus();
});

// `retry`: while the mountpoint is being created again, ask again (bounded).
async function openViewer(link, { retry = false } = {}) {
  const page = await browser.newPage();
  await page.goto(`${server.url}${link.watch_url}`);
  for (let attempt = 0; ; attempt += 1) {
    if (attempt > 0) await page.reload();  // the same link: only its fragment would change nothing
    await until(page, () => window.caustic.connection === 'live' || window.caustic.error, 30, 'a live connection');
    const error = await page.evaluate(() => window.caustic.error);
    if (!error) break;
    if (!retry || attempt >= 40) assert.fail(`the viewer failed: ${error}`);
    await page.waitForTimeout(250);
  }
  await until(page, framesDecoded, 30, 'a decoded frame');
  return page;
}

test('viewers of one broadcast all see it, a late joiner at once, and the holder\'s changes', async () => {
  const created = await api('POST', '/api/v1/sessions', { scene: 'wavy', mode: 'broadcast' });
  assert.equal(created.status, 201, JSON.stringify(created.body));
  const session = created.body;
  const link = (await api('POST', session.viewers_url, null, session.token)).body;
  const pages = [];
  for (let i = 0; i < VIEWERS; i += 1) pages.push(await openViewer(link));

  // The holder drags the light for 3 s: Janus forwards every frame sent to
  // every viewer, and each decodes them (as far as this loaded machine,
  // which also runs the server and the other viewers, lets it).
  const before = await sentFrames();
  const count = (name) => Promise.all(pages.map((p) => p.evaluate(videoStat, name)));
  const receivedBefore = await count('framesReceived');
  const decodedBefore = await count('framesDecoded');
  let version = 0;
  for (let i = 0; i < 90; i += 1) {
    const r = await api('PATCH', `${session.url}/params`, { light: { direction: [0.2 * Math.sin(i / 10), 0.1, -1] } },
                        session.token);
    version = r.body.version;
    await new Promise((resolve) => setTimeout(resolve, 33));
  }
  // Until the last frames have arrived everywhere (counts stand still; bounded).
  let received = [];
  for (let i = 0; i < 20; i += 1) {
    await new Promise((resolve) => setTimeout(resolve, 500));
    const now = (await count('framesReceived')).map((n, k) => n - receivedBefore[k]);
    if (JSON.stringify(now) === JSON.stringify(received)) break;
    received = now;
  }
  const sent = (await sentFrames()) - before;
  const decoded = (await count('framesDecoded')).map((n, i) => n - decodedBefore[i]);
  console.log(`frames sent ${sent}; received by each viewer ${received.join(', ')}; decoded ${decoded.join(', ')}`);
  assert.ok(sent > 20, `the server sent only ${sent} frames while the light moved`);
  for (const n of received) assert.ok(n >= 0.9 * sent, `a viewer received ${n} of ${sent} frames`);
  for (const n of decoded) assert.ok(n >= 0.5 * sent, `a viewer decoded ${n} of ${sent} frames`);
  // Every viewer hears of the last version on the frames channel.
  for (const p of pages) await until(p, (v) => window.caustic.version >= v, 20, `version ${version}`, version);
  mkdirSync(shots, { recursive: true });
  await pages[0].screenshot({ path: `${shots}/broadcast-viewer.png` });

  // A late joiner: its first frame follows its connection at once.
  const late = await browser.newPage();
  await late.goto(`${server.url}${link.watch_url}`);
  await until(late, () => window.caustic.firstFrameAt > 0, 30, 'the late joiner\'s first frame');
  const wait = await late.evaluate(() => Math.max(0, window.caustic.firstFrameAt - window.caustic.connectedAt));
  console.log(`late joiner: first frame ${wait.toFixed(0)} ms after its connection`);
  assert.ok(wait < 3000, `the late joiner waited ${wait} ms`);  // the goal, 500 ms, is a benchmark figure
  pages.push(late);

  // Janus restarts: the mountpoint comes back and a viewer can rejoin with the same link.
  await stopJanus();
  await startJanus();
  const again = await openViewer(link, { retry: true });
  assert.ok((await again.evaluate(framesDecoded)) > 0);
  for (const p of [...pages, again]) await p.close();
  assert.equal((await api('DELETE', session.url, null, session.token)).status, 204);
});
