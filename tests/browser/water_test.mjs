// SPDX-License-Identifier: LGPL-2.1-or-later
// The pool scene in the viewer, in Debian's chromium against a real
// `causticd serve` on 127.0.0.1: the water surface each shown frame carries
// is drawn and moves, a click on the water drops a stone that a later frame
// shows, a click beside the pool drops nothing, and the panel pauses and
// resumes the water. Every wait is bounded; no frame rate is assumed (the
// pool streams slowly on a software renderer).
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { launchChromium } from './chromium.mjs';
import { shots, until, withServer } from './harness.mjs';

let browser;
before(async () => {
  browser = await launchChromium();
});
after(async () => { await browser?.close(); });

// Where the water's point (x, y) is on the page, checked to be on the
// canvas itself (not under the panel, the header or the toolbar).
async function onCanvas(page, x, y) {
  const [px, py] = await page.evaluate(([a, b]) => window.caustic.waterPagePoint(a, b), [x, y]);
  const hit = await page.evaluate(([a, b]) => document.elementFromPoint(a, b)?.tagName, [px, py]);
  assert.equal(hit, 'CANVAS', `the water's point (${x}, ${y}) is under ${hit} at ${px}, ${py}`);
  return [px, py];
}

// The shown frames' water from now until `frames` more have been drawn:
// the first and last step (a solver's steps only grow) and the updates.
async function stepsOver(page, frames, seconds, what) {
  const from = await page.evaluate(() => ({ ...window.caustic.water }));
  const to = await until(page, (u) => window.caustic.water.updates >= u && { ...window.caustic.water },
                         seconds, what, from.updates + frames);
  return { first: from.step, last: to.step, updates: to.updates - from.updates };
}

test('the pool: the shown frames\' water is drawn and moves; a click drops a stone; the panel pauses the water', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.setViewportSize({ width: 1280, height: 800 });
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    const drops = [];
    page.on('request', (r) => { if (r.url().endsWith('/drops')) drops.push(r.postDataJSON()); });
    await page.goto(`${server.url}/viewer.html?scene=pool&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'a live connection');
    await until(page, () => window.caustic.water?.updates >= 1, 60, 'the first water surface drawn');

    // The surface drawn is the frame's: 32 x 32 heights of millimetres, and
    // it changes from frame to frame as the rain falls.
    const first = await page.evaluate(() => ({ water: { ...window.caustic.water }, heights: window.caustic.waterHeights() }));
    assert.equal(first.water.n, 32);
    assert.equal(first.heights.length, 32 * 32);
    assert.ok(first.heights.every((h) => Math.abs(h) < 0.05), 'heights beyond 5 cm');
    assert.ok(first.heights.some((h) => h !== 0), 'a flat surface');
    const moved = await until(page, (was) => {
      const h = window.caustic.waterHeights();
      return window.caustic.water.step > was.step && h.some((v, i) => v !== was.heights[i]) &&
        { step: window.caustic.water.step, updates: window.caustic.water.updates };
    }, 30, 'the surface moving', { step: first.water.step, heights: first.heights });
    console.log(`water: step ${first.water.step} -> ${moved.step} over ${moved.updates - first.water.updates} drawn surfaces`);
    // The slab that stands in for an object is not drawn over the water.
    assert.equal(await page.evaluate(() => window.caustic.surfaces().length), 1);

    // A click on the water (a press and release in place) drops a stone there.
    const [px, py] = await onCanvas(page, 0.3, -0.2);
    const answered = page.waitForResponse((r) => r.url().endsWith('/drops'), { timeout: 15000 });
    await page.mouse.click(px, py);
    const response = await answered;
    assert.equal(response.status(), 202);
    const drop = await response.json();
    const sent = drops.at(-1);
    assert.ok(Math.abs(sent.x - 0.3) < 0.05 && Math.abs(sent.y + 0.2) < 0.05, `the drop fell at ${sent.x}, ${sent.y}`);
    assert.ok(Number.isInteger(drop.drop) && drop.drop >= 1, JSON.stringify(drop));
    const shown = await until(page, (n) => window.caustic.water.drops >= n && { ...window.caustic.water.lastDrop }, 30,
                              `drop ${drop.drop} in a shown frame`, drop.drop);
    assert.equal(shown.drop, drop.drop);
    // Counted in the page: 0 when the frame with the drop was shown before the answer arrived.
    console.log(`drop ${drop.drop} shown ${shown.shownAt - shown.acceptedAt} drawn surfaces ` +
                `(${(shown.shownMs - shown.acceptedMs).toFixed(0)} ms) after the page had the server's 202`);
    // The hook's click takes the same path.
    const again = await page.evaluate(() => window.caustic.clickWater(-0.4, 0.5));
    assert.equal(again.status, 202);
    assert.equal(again.body.drop, drop.drop + 1);

    // A drag orbits the camera and drops nothing; neither does a click beside the pool.
    const posted = drops.length;
    const camera = await page.evaluate(() => window.caustic.cameraPosition());
    await page.mouse.move(px, py);
    await page.mouse.down();
    await page.mouse.move(px + 80, py + 10, { steps: 6 });
    await page.mouse.up();
    assert.notDeepEqual(await page.evaluate(() => window.caustic.cameraPosition()), camera, 'the drag did not orbit');
    await page.locator('.lil-controller', { hasText: 'Reset view' }).locator('button').click();
    const [ox, oy] = await onCanvas(page, 1.7, 0.4);
    await page.mouse.click(ox, oy);
    assert.equal(await page.evaluate(() => window.caustic.clickWater(2.5, 0)), null);
    await page.waitForTimeout(500);
    assert.equal(drops.length, posted, `posted ${JSON.stringify(drops.slice(posted))}`);
    assert.equal(await page.evaluate(() => window.caustic.water.posted), posted);

    // A drop the server refuses says why where the page shows warnings.
    const refused = await page.evaluate(() => window.caustic.dropAt(1.5, 0));
    assert.equal(refused.status, 422);
    await until(page, () => !document.getElementById('warnings').hidden, 5, 'the refusal on the page');
    assert.match(await page.textContent('#warnings'), /^drop: x: must lie in the pool/);

    // The panel's water folder: paused stops the solver, the frames keep coming.
    const paused = page.locator('.lil-controller', { hasText: 'paused' }).locator('input');
    await paused.check();
    await until(page, () => window.caustic.params.water.paused === true &&
                window.caustic.shownVersion >= window.caustic.version, 30, 'the paused version on screen');
    await stepsOver(page, 2, 30, 'frames after the pause');  // any frame made before the pause reached the solver
    const still = await stepsOver(page, 4, 60, 'frames of the paused water');
    console.log(`paused: step ${still.first} -> ${still.last} over ${still.updates} drawn surfaces`);
    assert.equal(still.last, still.first, 'the water moved while paused');
    await paused.uncheck();
    await until(page, () => window.caustic.params.water.paused === false &&
                window.caustic.shownVersion >= window.caustic.version, 30, 'the resumed version on screen');
    const resumed = await stepsOver(page, 4, 60, 'frames of the resumed water');
    console.log(`resumed: step ${resumed.first} -> ${resumed.last} over ${resumed.updates} drawn surfaces`);
    assert.ok(resumed.last > resumed.first, 'the water stayed still after resuming');

    // The wave strength slider goes through the same patches.
    const strength = page.locator('.lil-controller', { hasText: 'wave strength' }).locator('input');
    await strength.fill('0.012');
    await strength.press('Enter');
    await until(page, () => window.caustic.params.water.rain_strength === 0.012, 15, 'the wave strength on the server');

    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: `${shots}/viewer-pool.png` });
    assert.deepEqual(errors, []);
    await page.close();
  });
});

test('a scene without water draws none and offers no water controls', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1, 30, 'live');
    assert.equal(await page.evaluate(() => window.caustic.water), undefined);
    assert.equal(await page.evaluate(() => window.caustic.waterHeights()), null);
    assert.equal(await page.locator('.lil-controller', { hasText: 'wave strength' }).count(), 0);
    // Reset scene asks nothing of water the scene lacks.
    await page.evaluate(() => window.caustic.resetScene());
    await until(page, () => window.caustic.version >= 2, 10, 'the reset answered');
    assert.deepEqual(errors, []);
    await page.close();
  });
});
