// SPDX-License-Identifier: LGPL-2.1-or-later
// Page-level latency benchmark (prints figures, asserts nothing): the time
// from a light change in the viewer to the first displayed frame that shows
// it, over N changes, in Debian's chromium against `causticd serve` on
// 127.0.0.1.
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules \
//     node bench/browser_latency.mjs [changes=100] [codec=vp8] [size=1024]
import { spawn } from 'node:child_process';
import readline from 'node:readline';

import { launchChromium } from '../tests/browser/chromium.mjs';

const [changes = 100, codec = 'vp8', size = 1024] = process.argv.slice(2);

const server = spawn(process.env.CAUSTICD, ['serve', '--port', '0', '--ice-address', '127.0.0.1', '--width', `${size}`,
                                            '--height', `${size}`], { stdio: ['ignore', 'pipe', 'ignore'] });
const url = (await new Promise((resolve) => readline.createInterface({ input: server.stdout }).once('line', resolve)))
                .replace('listening on ', '').replace(/\/$/, '');
const browser = await launchChromium();
try {
  const page = await browser.newPage();
  await page.goto(`${url}/viewer.html?scene=wavy&codec=${codec}`);
  await page.waitForFunction(() => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1,
                             null, { timeout: 60000 });
  for (let i = 0; i < changes; ++i) {
    await page.evaluate((k) => window.caustic.moveLight(0.6 * Math.sin(k), 0.6 * Math.cos(k), 0), i);
    // Wait (bounded) for this change on screen before the next one.
    await page.waitForFunction(() => window.caustic.shownVersion >= window.caustic.version, null, { timeout: 10000 })
        .catch(() => {});
    if ((i + 1) % 20 === 0) console.log(`  ${i + 1}/${changes} changes`);
  }
  const l = (await page.evaluate(() => window.caustic.latencies)).sort((a, b) => a - b);
  const at = (p) => l[Math.min(l.length - 1, Math.round(p * (l.length - 1)))];
  console.log(`${codec} ${size}x${size}: light change -> frame on screen: median ${at(0.5).toFixed(0)} ms, ` +
              `p95 ${at(0.95).toFixed(0)} ms over ${l.length} changes`);
  // Where the browser's share goes: its jitter buffer and its decoder.
  const r = await page.evaluate(async () => {
    let v = null;
    (await window.caustic.peer.getStats()).forEach((s) => { if (s.type === 'inbound-rtp' && s.kind === 'video') v = s; });
    return v;
  });
  if (r) {
    console.log(`  browser: decoder ${r.decoderImplementation}, ${r.framesDecoded} frames decoded, ` +
                `${(1000 * r.totalDecodeTime / r.framesDecoded).toFixed(1)} ms decoding each, ` +
                `${(1000 * r.jitterBufferDelay / r.jitterBufferEmittedCount).toFixed(0)} ms in the jitter buffer each, ` +
                `${r.framesDropped ?? 0} dropped, ${r.freezeCount ?? 0} freezes`);
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
