// SPDX-License-Identifier: LGPL-2.1-or-later
// Gallery and viewer as a visitor sees them, on a laptop (1280x800) and a
// phone (390x844, touch), from a real `causticd serve` on loopback. Writes
// gallery-desktop.png, gallery-phone.png, viewer-<scene>-desktop.png,
// viewer-<scene>-desktop-high.png (the room's high quality, forced) and
// viewer-<scene>-phone.png into the folder given (docs/web-client/ holds the
// committed set). Every wait is bounded.
//
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules \
//     node bench/screenshots.mjs docs/web-client [scene ...]
import { spawn } from 'node:child_process';
import { mkdirSync, mkdtempSync } from 'node:fs';
import readline from 'node:readline';

import { launchChromium } from '../tests/browser/chromium.mjs';

const out = process.argv[2] ?? '/tmp/screenshots';
const scenes = process.argv.length > 3 ? process.argv.slice(3) : ['lens', 'wavy'];
const viewports = {
  desktop: { viewport: { width: 1280, height: 800 } },
  phone: { viewport: { width: 390, height: 844 }, isMobile: true, hasTouch: true, deviceScaleFactor: 1 },
};

const server = spawn(process.env.CAUSTICD, ['serve', '--port', '0', '--ice-address', '127.0.0.1'], {
  stdio: ['ignore', 'pipe', 'inherit'], env: { ...process.env, XDG_STATE_HOME: mkdtempSync('/tmp/causticd-state-') },
});
const url = await new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error('server did not start')), 30000);
  readline.createInterface({ input: server.stdout }).once('line', (l) => {
    clearTimeout(timer);
    resolve(l.replace('listening on ', '').replace(/\/$/, ''));
  });
});

async function until(page, fn, seconds, what) {
  for (let waited = 0; waited < seconds * 1000; waited += 250) {
    if (await page.evaluate(fn)) return;
    await page.waitForTimeout(250);
  }
  throw new Error(`timed out after ${seconds} s waiting for ${what}`);
}

const browser = await launchChromium();
try {
  mkdirSync(out, { recursive: true });
  for (const [name, options] of Object.entries(viewports)) {
    const context = await browser.newContext(options);
    const page = await context.newPage();
    await page.goto(`${url}/`);
    await page.waitForSelector('.card img', { timeout: 15000 });
    await until(page, () => [...document.images].every((i) => i.complete && i.naturalWidth > 0), 30, 'thumbnails');
    await page.screenshot({ path: `${out}/gallery-${name}.png` });
    for (const scene of scenes) {
      await page.goto(`${url}/viewer.html?scene=${scene}`);
      await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1, 60, 'live');
      // Auto exposure eases in over a fraction of a second; let it settle.
      await page.waitForTimeout(2500);
      await page.screenshot({ path: `${out}/viewer-${scene}-${name}.png` });
      console.log(`${out}/viewer-${scene}-${name}.png`, await page.evaluate(() => `${window.caustic.quality} room`));
      if (name !== 'desktop') continue;
      // The room as a machine with a GPU draws it (here it is slower than 30 fps).
      await page.goto(`${url}/viewer.html?scene=${scene}&quality=high`);
      await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1, 60, 'live');
      await page.waitForTimeout(2500);
      await page.screenshot({ path: `${out}/viewer-${scene}-${name}-high.png` });
    }
    await context.close();
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
