// SPDX-License-Identifier: LGPL-2.1-or-later
// The browser client in Debian's chromium, driven by playwright-core, against
// a real `causticd serve` on 127.0.0.1 (ICE pinned to loopback). Every wait
// is bounded.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { launchChromium } from './chromium.mjs';
import { shots, until, withServer } from './harness.mjs';
import { dragGizmo, framesDecoded, greyLevels } from './viewer_probes.mjs';

let browser;
before(async () => {
  browser = await launchChromium();
});
after(async () => { await browser?.close(); });

test('the gallery lists every scene with its rendered thumbnail', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/`);
    await page.waitForSelector('.card img', { timeout: 15000 });
    await until(page, () => [...document.images].every((i) => i.complete && i.naturalWidth === 256), 15, 'thumbnails');
    const ids = await page.$$eval('.card', (cards) => cards.map((c) => c.dataset.scene).sort());
    const builtIn = process.env.CAUSTIC_DESIGN_BUILT_IN === '1';
    const want = ['biconvex', 'cloth', 'cylinder', 'lens', 'pool', 'pool-walls', 'prism', 'room', 'slab', 'vase', 'wavy',
                  ...(builtIn ? ['design-logo', 'design-text'] : [])];
    for (const id of want) assert.ok(ids.includes(id), id);
    // Designed objects first, under their own heading; the classics below.
    const designed = await page.$$eval('#designed .card[data-scene]', (cards) => cards.map((c) => c.dataset.scene));
    const classics = await page.$$eval('#classics .card', (cards) => cards.map((c) => c.dataset.scene).sort());
    assert.ok(designed.every((id) => id.startsWith('design-')) && designed.length >= (builtIn ? 2 : 0), designed.join());
    assert.deepEqual(classics, ['biconvex', 'cloth', 'cylinder', 'lens', 'pool', 'pool-walls', 'prism', 'room', 'slab', 'vase', 'wavy']);
    assert.equal(await page.locator('#upload input[type=file]').count(), 1);
    mkdirSync(shots, { recursive: true });
    await page.setViewportSize({ width: 1280, height: 900 });
    await page.screenshot({ path: `${shots}/gallery.png`, fullPage: true });
    // A card is a plain link with the codec in it: a new tab (Ctrl/Cmd-click) opens the same.
    const href = () => page.getAttribute('.card[data-scene="lens"]', 'href');
    assert.equal(await href(), 'viewer.html?scene=lens&codec=vp8');
    await page.selectOption('#codec', 'h264');
    assert.equal(await href(), 'viewer.html?scene=lens&codec=h264');
    await page.selectOption('#codec', 'vp8');
    assert.equal(await page.locator('link[rel=icon]').count(), 1, 'no icon of its own: the browser asks /favicon.ico');
    await page.click('.card[data-scene="lens"]');
    await page.waitForURL(/viewer\.html\?scene=lens&codec=vp8/, { timeout: 10000 });
    await page.close();
  });
});

test('a picture uploaded on the gallery page becomes a live streamed scene', async (t) => {
  if (process.env.CAUSTIC_DESIGN_BUILT_IN !== '1') return t.skip('built without the designer');
  await withServer(['--set', 'design_resolution=128'], async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/`);
    await page.waitForSelector('#upload input[type=file]', { timeout: 15000 });
    // Any real PNG will do: the lens scene's thumbnail.
    const png = Buffer.from(await (await fetch(`${server.url}/api/v1/scenes/lens/thumbnail.png`)).arrayBuffer());
    await page.fill('#upload input[name=name]', 'Test picture');
    await page.check('#upload input[name=colour]');
    await page.setInputFiles('#upload input[type=file]', { name: 'lens.png', mimeType: 'image/png', buffer: png });
    await page.waitForURL(/viewer\.html\?scene=[0-9a-f]{32}&codec=vp8/, { timeout: 120000 });
    // The box asked for a colour design.
    const id = new URL(page.url()).searchParams.get('scene');
    const design = await (await fetch(`${server.url}/api/v1/designs/${id}`)).json();
    assert.equal(design.colour, true);
    await until(page, () => window.caustic.connection === 'live', 30, 'a live connection');
    await until(page, framesDecoded, 30, 'decoded frames');
    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: `${shots}/viewer-upload.png` });
    await page.close();
  });
});

for (const codec of ['vp8', 'h264']) {
  test(`the viewer shows live ${codec} video and follows the light`, async () => {
    await withServer(async (server) => {
      const page = await browser.newPage();
      await page.goto(`${server.url}/viewer.html?scene=wavy&codec=${codec}`);
      await until(page, () => window.caustic.connection === 'live', 30, 'a live connection');
      const first = await until(page, framesDecoded, 30, 'decoded frames');
      let decoded = first;
      for (let waited = 0; decoded <= first + 10 && waited < 30000; waited += 250) {
        await page.waitForTimeout(250);
        decoded = await page.evaluate(framesDecoded);
      }
      assert.ok(decoded > first + 10, `framesDecoded stayed at ${decoded}`);
      const size = await page.evaluate(() => [document.getElementById('video').videoWidth,
                                              document.getElementById('video').videoHeight]);
      assert.deepEqual(size, [320, 240]);
      // The browser took the server's "no playout delay" (RTP header extension).
      const answer = await page.evaluate(() => window.caustic.peer.currentLocalDescription.sdp);
      assert.match(answer, /a=extmap:\d+ http:\/\/www\.webrtc\.org\/experiments\/rtp-hdrext\/playout-delay\r\n/);
      await until(page, () => window.caustic.shownVersion === 1, 20, 'frame version 1 on screen');
      // The scene's name, in the page and its title.
      assert.equal(await page.textContent('#title'), 'Wavy window');
      assert.match(await page.title(), /^Wavy window/);

      const sceneLight = await page.evaluate(() => JSON.stringify(window.caustic.params.light));
      const before = await page.evaluate(greyLevels, '#video');
      await page.evaluate(() => window.caustic.moveLight(4, 2.5, 0));
      await until(page, () => window.caustic.version >= 2 && window.caustic.shownVersion >= window.caustic.version,
                  30, 'the new version on screen');
      await page.waitForTimeout(300);
      const after = await page.evaluate(greyLevels, '#video');
      const change = after.reduce((sum, v, i) => sum + Math.abs(v - before[i]), 0) / after.length;
      assert.ok(change > 1, `the picture barely changed (${change})`);
      assert.match(await page.textContent('#version'), /frame version [2-9]/);
      // The stats overlay says what fidelity auto renders and that the light has left the calibration.
      await page.evaluate(() => { document.getElementById('stats').hidden = false; });
      await until(page, () => document.getElementById('stats').textContent.includes('fidelity'), 5, 'the stats overlay');
      const stats = await page.textContent('#stats');
      assert.match(stats, /fidelity auto: \d+\u00b2 mesh \(\d+ vertices\), exact point model, Fresnel on; expected L1 \d+\.\d+% \(target 5\.0%\)/);
      assert.match(stats, /calibrated before the scene was changed/);

      mkdirSync(shots, { recursive: true });
      await page.screenshot({ path: `${shots}/viewer-${codec}.png` });
      // Not blank: the lightmap's area on the canvas is brighter than the rest.
      const grey = (await page.evaluate(greyLevels, '#stage canvas')).sort((a, b) => a - b);
      const contrast = grey[Math.floor(grey.length * 0.99)] - grey[Math.floor(grey.length * 0.5)];
      assert.ok(contrast > 60, `the canvas looks blank (contrast ${contrast})`);
      if (codec === 'vp8') {
        // '?' opens the help with the keys and gestures; '?' again closes it; so does its button.
        await page.keyboard.press('?');
        await until(page, () => !document.getElementById('help').hidden, 5, 'the help shown');
        assert.match(await page.textContent('#help'), /light mode/);
        await page.keyboard.press('?');
        await until(page, () => document.getElementById('help').hidden, 5, 'the help closed');
        await page.click('#help-button');
        await until(page, () => !document.getElementById('help').hidden, 5, 'the help shown by its button');
        await page.click('#help-button');
        // Escape closes it as well and gives the focus back to what had it.
        await page.keyboard.press('?');
        await until(page, () => document.activeElement === document.getElementById('help'), 5, 'the help focused');
        await page.keyboard.press('Escape');
        await until(page, () => document.getElementById('help').hidden && document.activeElement?.id === 'help-button', 5,
                    'the help closed by Escape, the focus back on its button');
        // A key with Ctrl, Alt or Meta is the browser's: Ctrl+L is not light mode.
        await page.keyboard.press('Control+l');
        await page.keyboard.press('Alt+r');
        await page.waitForTimeout(200);
        assert.equal(await page.evaluate(() => window.caustic.mode), 'none');
        // Reset scene: the light goes back to where the scene has it.
        assert.notEqual(await page.evaluate(() => JSON.stringify(window.caustic.params.light)), sceneLight);
        await page.evaluate(() => window.caustic.resetScene());
        await until(page, (want) => JSON.stringify(window.caustic.params.light) === want, 10, 'the scene\'s light back',
                    sceneLight);
        // A mirror sends the light away from the screen below it: the page says so, and stops saying so.
        await page.evaluate(() => window.caustic.setParams({ object: { material: 'reflective' } }));
        await until(page, () => !document.getElementById('warnings').hidden, 10, 'the warning on the page');
        assert.match(await page.textContent('#warnings'), /object\.material: no light reaches the screen/);
        await page.evaluate(() => window.caustic.setParams({ object: { material: 'refractive' } }));
        await until(page, () => document.getElementById('warnings').hidden, 10, 'the warning gone');
        // The panel's glass: the server's catalogue on offer; choosing one makes the
        // object dispersive, "none" takes it away again (a null would restore the scene's).
        const glass = page.locator('.lil-controller', { hasText: 'glass (dispersion)' }).locator('select');
        const offered = await glass.locator('option').allTextContents();
        for (const name of ['none', 'bk7', 'water']) assert.ok(offered.includes(name), offered.join());
        await glass.selectOption('bk7');
        await until(page, () => window.caustic.params.object.glass === 'bk7', 10, 'the glass on the server');
        assert.ok(Math.abs(await page.evaluate(() => window.caustic.params.object.ior) - 1.5168) < 1e-3);
        await glass.selectOption('none');
        await until(page, () => window.caustic.params.object.glass === null, 10, 'the glass taken away');
      }
      await page.close();
    });
  });
}

test('a scene with receivers lays each tile of the picture onto its own surface', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/viewer.html?scene=room&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'a live connection');
    await until(page, () => window.caustic.shownVersion >= 1, 30, 'the first frame on screen');
    // The wall (the screen) shows the left half of the picture, the floor the right.
    const atlas = await page.evaluate(() => window.caustic.atlas);
    assert.equal(atlas.length, 2);
    const surfaces = await page.evaluate(() => window.caustic.surfaces());
    assert.equal(surfaces.length, 2);
    assert.deepEqual(surfaces.map((s) => s.repeat), [[0.5, 1], [0.5, 1]]);
    assert.deepEqual(surfaces.map((s) => s.offset), [[0, 0], [0.5, 0]]);
    // Each hangs on its own surface: the wall at x = 18, the floor 30 below.
    assert.ok(Math.abs(surfaces[0].centre[0] - 18) < 0.1, surfaces[0].centre.join());
    assert.ok(Math.abs(surfaces[1].centre[2] + 30) < 0.1, surfaces[1].centre.join());
    await page.waitForTimeout(500);
    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: `${shots}/viewer-room.png` });
    await page.close();
  });
});

// A lathe (the vase) and a mesh the scene brings (the cloth): each wears its tile round its body.
for (const [scene, shape, foot] of [['vase', 'LatheGeometry', [17, 0, -30]], ['cloth', 'BufferGeometry', [15, 0, -29.99]]]) {
  test(`the ${scene} among the receivers wears its tile of the picture on its body`, async () => {
    await withServer(async (server) => {
      const page = await browser.newPage();
      await page.goto(`${server.url}/viewer.html?scene=${scene}&codec=vp8`);
      await until(page, () => window.caustic.connection === 'live', 30, 'a live connection');
      await until(page, () => window.caustic.shownVersion >= 1, 30, 'the first frame on screen');
      // The table (the screen) shows the left half of the picture, the shape the right.
      const surfaces = await page.evaluate(() => window.caustic.surfaces());
      assert.deepEqual(surfaces.map((s) => s.shape), ['PlaneGeometry', shape]);
      assert.deepEqual(surfaces.map((s) => s.repeat), [[0.5, 1], [0.5, 1]]);
      assert.deepEqual(surfaces.map((s) => s.offset), [[0, 0], [0.5, 0]]);
      assert.deepEqual(surfaces[1].centre, foot);  // its frame's origin: a lathe's foot, a mesh's centre
      await page.waitForTimeout(500);
      mkdirSync(shots, { recursive: true });
      await page.screenshot({ path: `${shots}/viewer-${scene}.png` });
      await page.close();
    });
  });
}

test('dragging the gizmos with the pointer moves the light and moves and turns the object on the server', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.setViewportSize({ width: 1000, height: 700 });
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion === 1, 30, 'live');
    // Light mode ('l'): the translate gizmo sits on the light marker; its
    // centre moves freely in the view plane. Pull it to the right.
    const before = await page.evaluate(() => window.caustic.params.light.direction);
    const [x] = await dragGizmo(page, 'l', 'light', 80, 0);
    const after = await page.evaluate(() => window.caustic.params.light.direction);
    const turned = Math.acos(before.reduce((s, v, i) => s + v * after[i], 0) /
                             (Math.hypot(...before) * Math.hypot(...after))) * 180 / Math.PI;
    assert.ok(turned > 1, `the light turned only ${turned} degrees (${before} -> ${after})`);
    // The marker followed the pointer on the page.
    const [x2] = await page.evaluate(() => window.caustic.pagePoint('light'));
    assert.ok(x2 > x + 40, `the marker stayed at ${x2} (grabbed at ${x})`);

    // The object's translate gizmo the same way ('t').
    const from = await page.evaluate(() => window.caustic.params.object.position);
    await dragGizmo(page, 't', 'object', -60, 20);
    const to = await page.evaluate(() => window.caustic.params.object.position);
    assert.ok(Math.hypot(to[0] - from[0], to[1] - from[1], to[2] - from[2]) > 1, `the object stayed at ${to}`);

    // And the rotate gizmo ('r'): its centre turns the object freely.
    const pose = await page.evaluate(() => window.caustic.params.object.rotation_deg);
    await dragGizmo(page, 'r', 'object', 50, 30);
    const turnedTo = await page.evaluate(() => window.caustic.params.object.rotation_deg);
    assert.ok(Math.max(...turnedTo.map((a, i) => Math.abs(a - pose[i]))) > 1, `the object kept its rotation ${turnedTo}`);
    await page.close();
  });
});

test('the synchronous pose holds the drawn slab until its frame arrives', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/viewer.html?scene=lens&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion === 1, 30, 'live');
    const [before, right_after] = await page.evaluate(() => {
      window.caustic.sync = true;
      const start = window.caustic.drawnProxy();
      window.caustic.moveObject(3, 0, 0);
      return [start, window.caustic.drawnProxy()];
    });
    assert.deepEqual(right_after, before);  // the frame with the move is not on screen yet
    await until(page, () => window.caustic.version >= 2 && window.caustic.shownVersion >= window.caustic.version,
                30, 'the moved frame on screen');
    await page.waitForTimeout(100);
    const moved = await page.evaluate(() => window.caustic.drawnProxy());
    assert.ok(Math.abs(moved[0] - before[0] - 3) < 1e-6, `drawn at ${moved}, requested ${before[0] + 3}`);
    // A turn happens about the object's origin, as the server turns it: the
    // slab's middle keeps its distance from the origin and moves around it.
    const origin = await page.evaluate(() => window.caustic.params.object.position);
    await page.evaluate(() => window.caustic.rotateObject(0, 30, 0));
    await until(page, () => window.caustic.version >= 3 && window.caustic.shownVersion >= window.caustic.version,
                30, 'the turned frame on screen');
    await page.waitForTimeout(100);
    const turned = await page.evaluate(() => window.caustic.drawnProxy());
    const from = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    assert.ok(from(moved, origin) > 0.5, `the slab's middle sits on the origin (${moved} vs ${origin})`);
    assert.ok(Math.abs(from(turned, origin) - from(moved, origin)) < 1e-6, `turned ${turned}, origin ${origin}`);
    assert.ok(from(turned, moved) > 0.5, `the middle stayed at ${turned}: turned about itself`);
    await page.close();
  });
});

test('a patch the server refuses for now (429) is said, sent again after Retry-After, and reaches the server', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    const patches = [];  // when each PATCH left the page
    let token = null, refused = 0;
    await page.route('**/params', async (route) => {
      const request = route.request();
      if (request.method() !== 'PATCH') return route.continue();
      patches.push(Date.now());
      token = request.headers().authorization;
      if (refused++ > 0) return route.continue();
      return route.fulfill({ status: 429, headers: { 'Retry-After': '1' }, contentType: 'application/problem+json',
                             body: JSON.stringify({ title: 'Too Many Requests', status: 429, detail: 'too many requests' }) });
    });
    const said = [];
    await page.exposeFunction('noteWarnings', (text) => said.push(text));
    await page.addInitScript(() => {
      addEventListener('DOMContentLoaded', () => {
        const warnings = document.getElementById('warnings');
        new MutationObserver(() => window.noteWarnings(warnings.textContent))
          .observe(warnings, { subtree: true, childList: true, characterData: true });
      });
    });
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion === 1, 30, 'live');
    // The second change waits while the first is in flight; when the first
    // is refused, it goes again with the second merged over it.
    await page.evaluate(() => {
      window.caustic.setParams({ post: { gamma: 2.5, bloom_strength: 0.2 } });
      window.caustic.setParams({ post: { bloom_strength: 0.7 } });
    });
    await until(page, () => window.caustic.params.post.gamma === 2.5 && window.caustic.params.post.bloom_strength === 0.7,
                15, 'both changes applied');
    assert.ok(said.some((w) => /too many requests; sending it again in 1 s/.test(w)), `the page said: ${said}`);
    assert.equal(patches.length, 2, `${patches.length} PATCHes: the refused one and its second try expected`);
    assert.ok(patches[1] - patches[0] >= 900, `sent again after ${patches[1] - patches[0]} ms, not after Retry-After`);
    const held = await (await fetch(`${server.url}/api/v1/sessions/${await page.evaluate(() => window.caustic.session.id)}/params`,
                                    { headers: { Authorization: token } })).json();
    assert.equal(held.params.post.gamma, 2.5);
    assert.equal(held.params.post.bloom_strength, 0.7);
    await until(page, () => document.getElementById('warnings').hidden, 5, 'the refusal gone once a patch is taken');
    await page.close();
  });
});

test('the upload card rides out a few polls without an answer and says why a design failed', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.route('**/api/v1/designs?*', (route) => route.fulfill({
      status: 202, contentType: 'application/json', body: JSON.stringify({ id: 'x', status_url: '/api/v1/designs/x' }),
    }));
    // A network blip, a proxy's HTML page between restarts, progress, then a failure the server gave no words.
    const polls = [(r) => r.abort('failed'),
                   (r) => r.fulfill({ status: 502, contentType: 'text/html', body: '<html>Bad Gateway</html>' }),
                   (r) => r.fulfill({ status: 200, contentType: 'application/json',
                                      body: JSON.stringify({ state: 'running', progress: 0.5, stage: 'transport' }) }),
                   (r) => r.fulfill({ status: 200, contentType: 'application/json',
                                      body: JSON.stringify({ state: 'failed', progress: 0.5, error: '' }) })];
    let polled = 0;
    await page.route('**/api/v1/designs/x', (route) => polls[Math.min(polled++, polls.length - 1)](route));
    await page.goto(`${server.url}/`);
    await page.waitForSelector('#upload input[type=file]', { timeout: 15000 });
    const png = Buffer.from(await (await fetch(`${server.url}/api/v1/scenes/lens/thumbnail.png`)).arrayBuffer());
    await page.setInputFiles('#upload input[type=file]', { name: 'lens.png', mimeType: 'image/png', buffer: png });
    await until(page, () => /^Not designed/.test(document.querySelector('.upload-status').textContent), 20, 'the outcome');
    assert.equal(await page.textContent('.upload-status'), 'Not designed: the designer could not make a lens of this picture');
    assert.equal(polled, 4);
    await page.close();
  });
});
