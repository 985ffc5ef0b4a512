// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's frame rate in headless Debian chromium (software WebGL), as
// requestAnimationFrame counts it, still and while the light is dragged
// (a scripted light move every 100 ms, the path a drag takes), for each
// room quality. Prints one line per case with the machine.
//
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules \
//     node bench/page_fps.mjs [scene] [seconds] [stream size]
import os from 'node:os';

import { launchChromium } from '../tests/browser/chromium.mjs';
import { startServer, until } from '../tests/browser/harness.mjs';

const scene = process.argv[2] ?? 'wavy';
const seconds = Number(process.argv[3] ?? 5);
const streamSize = Number(process.argv[4] ?? 1024);

// Frames the page draws in `ms` (while the light moves, with `drag`),
// counted by its own requestAnimationFrame.
const countFrames = ([ms, drag]) => new Promise((resolve) => {
  const timer = drag ? setInterval(() => window.caustic.moveLight(0.3, 0, 0), 100) : null;
  let frames = 0;
  const start = performance.now();
  const tick = (now) => {
    if (now - start >= ms) {
      clearInterval(timer);
      return resolve((1000 * frames) / (now - start));
    }
    ++frames;
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
});

const server = await startServer([], { width: streamSize, height: streamSize });
const browser = await launchChromium();
try {
  console.log(`machine: ${os.cpus()[0].model}, ${os.cpus().length} cores; chromium software WebGL; stream ${streamSize}x${streamSize} VP8; page 1280x800`);
  for (const quality of ['high', 'low']) {
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    await page.goto(`${server.url}/viewer.html?scene=${scene}&codec=vp8&quality=${quality}`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1, 60, 'live');
    await page.waitForTimeout(1500);
    const still = await page.evaluate(countFrames, [seconds * 1000, false]);
    const drag = await page.evaluate(countFrames, [seconds * 1000, true]);
    console.log(`${scene} room ${quality}: ${still.toFixed(1)} fps still, ${drag.toFixed(1)} fps during a light drag`);
    await page.close();
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
