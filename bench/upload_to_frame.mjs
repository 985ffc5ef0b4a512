// SPDX-License-Identifier: LGPL-2.1-or-later
// Upload-to-first-frame benchmark (prints figures, asserts nothing): a
// visitor's picture chosen on the gallery page's upload card, designed by
// the server, opened in the viewer, until its first video frame is decoded;
// in Debian's chromium against `causticd serve` on 127.0.0.1, N uploads.
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules \
//     node bench/upload_to_frame.mjs PICTURE.png [uploads=3] [size=1024]
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { cpus } from 'node:os';
import path from 'node:path';
import readline from 'node:readline';

import { launchChromium } from '../tests/browser/chromium.mjs';

const [picture, uploads = 3, size = 1024] = process.argv.slice(2);
if (!picture) {
  console.error('usage: node bench/upload_to_frame.mjs PICTURE.png [uploads] [size]');
  process.exit(2);
}
const bytes = readFileSync(picture);
const mimeType = picture.endsWith('.png') ? 'image/png' : 'image/jpeg';

const server = spawn(process.env.CAUSTICD, ['serve', '--port', '0', '--ice-address', '127.0.0.1', '--width', `${size}`,
                                            '--height', `${size}`], {
  stdio: ['ignore', 'pipe', 'ignore'],
  env: { ...process.env, XDG_STATE_HOME: mkdtempSync('/tmp/causticd-bench-state-') },
});
const url = (await new Promise((resolve) => readline.createInterface({ input: server.stdout }).once('line', resolve)))
                .replace('listening on ', '').replace(/\/$/, '');
const browser = await launchChromium();
console.log(`machine: ${cpus().length} x ${cpus()[0].model}; picture ${path.basename(picture)}; stream ${size}x${size}`);
const rows = [];
try {
  for (let i = 0; i < uploads; ++i) {
    const page = await browser.newPage();
    await page.goto(`${url}/`);
    await page.waitForSelector('#upload input[type=file]');
    const start = Date.now();
    await page.setInputFiles('#upload input[type=file]', { name: path.basename(picture), mimeType, buffer: bytes });
    await page.waitForURL(/viewer\.html/, { timeout: 120000 });
    const ready = Date.now() - start;
    await page.waitForFunction(() => window.caustic?.peer, null, { timeout: 60000 });
    await page.waitForFunction(() => window.caustic.peer.getStats().then((r) => {
      let n = 0;
      r.forEach((s) => { if (s.type === 'inbound-rtp' && s.kind === 'video') n = s.framesDecoded; });
      return n > 0;
    }), null, { timeout: 60000, polling: 20 });
    const frame = Date.now() - start;
    rows.push({ ready, frame });
    console.log(`  upload ${i + 1}: designed and viewer open ${(ready / 1000).toFixed(2)} s, ` +
                `first frame decoded ${(frame / 1000).toFixed(2)} s`);
    await page.close();
  }
  const median = (xs) => xs.sort((a, b) => a - b)[Math.floor(xs.length / 2)];
  console.log(`upload -> first streamed frame: median ${(median(rows.map((r) => r.frame)) / 1000).toFixed(2)} s ` +
              `(designed: ${(median(rows.map((r) => r.ready)) / 1000).toFixed(2)} s) over ${rows.length} uploads`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
