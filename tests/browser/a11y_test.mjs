// SPDX-License-Identifier: LGPL-2.1-or-later
// The pages for visitors without a mouse, with a screen reader, large text
// or a phone (WCAG 2.1 AA as the yardstick): keyboard paths and focus, names
// and landmarks, live regions that are not chatty, contrast and layout, and
// the failures a browser can bring (no WebGL, no WebRTC, no server) said in
// words. Every wait is bounded.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { launchChromium } from './chromium.mjs';
import { shots, until, withServer } from './harness.mjs';

let browser;
before(async () => { browser = await launchChromium(); });
after(async () => { await browser?.close(); });

const live = () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1;
const focused = () => {
  const e = document.activeElement;
  return e.id || e.dataset.mode || e.getAttribute('aria-label') || e.textContent.trim().slice(0, 30);
};
// What a screen reader reads of the element `selector`: its text less the
// parts hidden from it.
const readable = (selector) => {
  const read = (node) => (node.nodeType === Node.TEXT_NODE ? node.textContent
    : node.getAttribute?.('aria-hidden') === 'true' ? '' : [...node.childNodes].map(read).join(''));
  return read(document.querySelector(selector));
};
// Whether two elements' boxes overlap.
const overlap = ([a, b]) => {
  const [r, s] = [document.querySelector(a).getBoundingClientRect(), document.querySelector(b).getBoundingClientRect()];
  return r.left < s.right && s.left < r.right && r.top < s.bottom && s.top < r.bottom;
};

test('a retry\'s countdown is seen but not read out each second', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.route('**/api/v1/sessions', (route) => (route.request().method() === 'POST' ? route.abort() : route.continue()));
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    // Two successive seconds of one countdown, as shown and as read.
    const seen = [];
    for (let waited = 0; waited < 60000 && !seen.some((s, i) => i && /in 1 s$/.test(s.shown) && /in 2 s$/.test(seen[i - 1].shown));
      waited += 100) {
      // (A string, as the page's policy allows no eval of its own.)
      const now = await page.evaluate(`({ shown: document.getElementById('state').textContent, read: (${readable})('#state') })`);
      if (now.shown !== seen.at(-1)?.shown) seen.push(now);
      await page.waitForTimeout(100);
    }
    const i = seen.findIndex((s, k) => k && /in 1 s$/.test(s.shown) && /in 2 s$/.test(seen[k - 1].shown));
    assert.ok(i > 0, `no countdown seen: ${seen.map((s) => s.shown).join(' | ')}`);
    assert.equal(seen[i].read, seen[i - 1].read, 'the countdown is read out each second');
    assert.equal(seen[i].read, 'reconnecting: the server does not answer');
    await page.close();
  });
});
