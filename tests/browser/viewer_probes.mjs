// SPDX-License-Identifier: LGPL-2.1-or-later
// What the viewer tests read from and do to a viewer page: functions that
// run inside the page (passed to page.evaluate or until) and a drag of the
// page's gizmos with the mouse.
import assert from 'node:assert/strict';

import { until } from './harness.mjs';

export const framesDecoded = () => window.caustic.peer?.getStats().then((report) => {
  let n = 0;
  report.forEach((r) => { if (r.type === 'inbound-rtp' && r.kind === 'video') n = r.framesDecoded; });
  return n;
});

// The grey levels (red channel) of what the element `selector` shows now:
// the video's current frame or a canvas's last drawing.
export const greyLevels = (selector) => {
  const e = document.querySelector(selector);
  const c = document.createElement('canvas');
  c.width = e.videoWidth ?? e.width;
  c.height = e.videoHeight ?? e.height;
  const g = c.getContext('2d');
  g.drawImage(e, 0, 0);
  return Array.from(g.getImageData(0, 0, c.width, c.height).data.filter((_, i) => i % 4 === 0));
};

// Switches the viewer to a control mode (its key), grabs the gizmo's centre
// on `what` ('light' or 'object') with the mouse, drags it by (dx, dy) pixels
// and waits for the resulting parameter version on screen. Returns where it
// grabbed.
export async function dragGizmo(page, key, what, dx, dy) {
  const version = await page.evaluate(() => window.caustic.version);
  await page.keyboard.press(key);
  await page.waitForTimeout(200);
  const [x, y] = await page.evaluate((w) => window.caustic.pagePoint(w), what);
  const { width, height } = page.viewportSize();
  assert.ok(x > 0 && x < width && y > 0 && y < height, `the ${what} is off the page at ${x}, ${y}`);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x + dx, y + dy, { steps: 8 });
  await page.mouse.up();
  await until(page, (v) => window.caustic.version > v && window.caustic.shownVersion >= window.caustic.version,
              30, `the dragged ${what} on screen`, version);
  return [x, y];
}
