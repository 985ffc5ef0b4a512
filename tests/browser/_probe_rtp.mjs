import { test, after } from 'node:test';
import { launchChromium } from './chromium.mjs';
import { until } from './harness.mjs';
import { api as call, Janus } from './janus_harness.mjs';
let janus, server, browser;
after(async () => { await browser?.close(); server?.kill('SIGTERM'); if (janus) await janus.stop(); });
test('probe', async () => {
  janus = await Janus.start();
  server = await janus.startServer();
  browser = await launchChromium();
  const api = (m, u, b, t) => call(server, m, u, b, t);
  const s = (await api('POST', '/api/v1/sessions', { scene: process.env.PROBE_SCENE ?? 'pool', mode: 'broadcast' })).body;
  const link = (await api('POST', s.viewers_url, null, s.token)).body;
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log('pageerror', e.message));
  await page.addInitScript(() => {
    window.__msgs = []; window.__shown = [];
    const Orig = window.RTCPeerConnection;
    window.RTCPeerConnection = function (...a) {
      const pc = new Orig(...a);
      const hook = (c) => c.addEventListener('message', ({ data }) => {
        const t = typeof data === 'string' ? data : new TextDecoder().decode(data);
        const m = JSON.parse(t); window.__msgs.push([performance.now(), m.rtp_timestamp, m.version, m.water?.step, !!m.params, m.params ? JSON.stringify(m.params.water) : '']);
      });
      pc.addEventListener('datachannel', ({ channel }) => hook(channel));
      const cdc = pc.createDataChannel.bind(pc);
      pc.createDataChannel = (...b) => { const c = cdc(...b); hook(c); return c; };
      return pc;
    };
    window.RTCPeerConnection.prototype = Orig.prototype;
    addEventListener('DOMContentLoaded', () => {
      const v = document.getElementById('video');
      const f = (now, meta) => { window.__shown.push([now, meta.rtpTimestamp]); v.requestVideoFrameCallback(f); };
      v.requestVideoFrameCallback(f);
    });
  });
  await page.goto(`${server.url}${link.watch_url}&view=video`);
  await until(page, () => window.caustic.connection === 'live', 30, 'live');
  await page.waitForTimeout(8000);
  const r = await page.evaluate(() => ({ msgs: window.__msgs, shown: window.__shown }));
  console.log('msgs', r.msgs.length, JSON.stringify(r.msgs.slice(0, 8)), JSON.stringify(r.msgs.slice(-5)));
  console.log('shown', r.shown.length, JSON.stringify(r.shown.slice(0, 8)), JSON.stringify(r.shown.slice(-5)));
  const ts = new Set(r.msgs.map((m) => m[1]));
  console.log('matched', r.shown.filter(([, t]) => ts.has(t)).length);
  await page.close();
});
