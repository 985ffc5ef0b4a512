// SPDX-License-Identifier: LGPL-2.1-or-later
// What one more viewer of a broadcast costs: causticd renders and encodes
// once, Janus forwards to every viewer. For N viewers (pages in one headless
// chromium) while the holder drags the light at 30 Hz, it measures over
// `seconds` the CPU of causticd and of Janus (% of one core, from /proc),
// Janus's memory, and the slowest viewer's frame rate; then the slope per
// viewer. The viewers' decoding shares this machine's cores with both
// servers, as real viewers' would not. Prints a table; asserts nothing.
// Runs in a network namespace of its own (Janus needs one for ICE; root):
//
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules CAUSTIC_JANUS_DIR=janus \
//     tests/janus/in_namespace.sh node bench/broadcast_bench.mjs [counts, e.g. 1,2,4,8] [seconds] [size]
import os from 'node:os';

import { launchChromium } from '../tests/browser/chromium.mjs';
import { until } from '../tests/browser/harness.mjs';
import { api, Janus, sentFrames, videoStat } from '../tests/browser/janus_harness.mjs';
import { cpuSeconds, rssMiB } from './proc_stats.mjs';

const counts = (process.argv[2] ?? '1,2,4,8').split(',').map(Number);
const seconds = Number(process.argv[3] ?? 10);
const size = Number(process.argv[4] ?? 1024);

const janus = await Janus.start();
const server = await janus.startServer([], { width: size, height: size });
const browser = await launchChromium();
console.log(`machine: ${os.cpus().length} cores, ${os.cpus()[0].model}; ${size}x${size} VP8 broadcast, holder dragging at 30 Hz, ${seconds} s per count`);
console.log('viewers | causticd CPU | Janus CPU | Janus RSS MiB | frames sent/s | slowest viewer fps');
const rows = [];
try {
  const session = (await api(server, 'POST', '/api/v1/sessions', { scene: 'wavy', mode: 'broadcast' })).body;
  const link = (await api(server, 'POST', session.viewers_url, null, session.token)).body;
  const pages = [];
  for (const n of counts) {
    while (pages.length < n) {
      const page = await browser.newPage();
      await page.goto(`${server.url}${link.watch_url}&view=video`);  // the forwarding, not WebGL rooms
      await until(page, () => window.caustic.connection === 'live', 60, 'a live viewer');
      pages.push(page);
    }
    const decoded0 = await Promise.all(pages.map((p) => p.evaluate(videoStat, 'framesDecoded')));
    const sent0 = await sentFrames(server);
    const cpu0 = [cpuSeconds(server.pid), cpuSeconds(janus.process.pid)];
    const start = performance.now();
    for (let i = 0; performance.now() - start < seconds * 1000; i += 1) {
      await api(server, 'PATCH', `${session.url}/params`, { light: { direction: [0.25 * Math.sin(i / 15), 0.1, -1] } },
                session.token);
      const due = start + (i + 1) * 33.3;
      await new Promise((resolve) => setTimeout(resolve, Math.max(0, due - performance.now())));
    }
    const wall = (performance.now() - start) / 1000;
    const cpu = [cpuSeconds(server.pid), cpuSeconds(janus.process.pid)].map((c, i) => (100 * (c - cpu0[i])) / wall);
    const decoded = await Promise.all(pages.map((p) => p.evaluate(videoStat, 'framesDecoded')));
    const slowest = Math.min(...decoded.map((d, i) => (d - decoded0[i]) / wall));
    const sent = ((await sentFrames(server)) - sent0) / wall;
    rows.push({ n, causticd: cpu[0], janus: cpu[1] });
    console.log(`${String(n).padStart(7)} | ${cpu[0].toFixed(1).padStart(11)}% | ${cpu[1].toFixed(1).padStart(8)}% | ` +
                `${rssMiB(janus.process.pid).toFixed(1).padStart(13)} | ${sent.toFixed(1).padStart(13)} | ${slowest.toFixed(1)}`);
  }
  if (rows.length > 1) {
    const [first, last] = [rows[0], rows[rows.length - 1]];
    const per = (key) => (last[key] - first[key]) / (last.n - first.n);
    console.log(`per extra viewer: causticd ${per('causticd').toFixed(2)}% of a core, Janus ${per('janus').toFixed(2)}% of a core`);
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
  await janus.stop();
}
