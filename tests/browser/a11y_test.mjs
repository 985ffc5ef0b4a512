// SPDX-License-Identifier: LGPL-2.1-or-later
// The pages for visitors without a mouse, with a screen reader, large text
// or a phone (WCAG 2.1 AA as the yardstick): keyboard paths and focus, names
// and landmarks, live regions that are not chatty, contrast and layout, and
// the failures a browser can bring (no WebGL, no WebRTC, no server) said in
// words; WCAG 2.2's target size (2.5.8) too. Every wait is bounded.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { focused, live, overlap, readable, recordStateReads, smallTargets } from './a11y_probes.mjs';
import { launchChromium } from './chromium.mjs';
import { shots, until, withServer } from './harness.mjs';

let browser;
before(async () => { browser = await launchChromium(); });
after(async () => { await browser?.close(); });

test('the gallery: landmarks, headings in order, named pictures and controls, the keyboard and a phone', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext({ viewport: { width: 360, height: 640 } });
    const page = await context.newPage();
    await page.goto(`${server.url}/`);
    await until(page, () => document.querySelectorAll('.card[data-scene]').length >= 11, 30, 'the cards');
    assert.equal(await page.getAttribute('html', 'lang'), 'en');
    assert.equal(await page.locator('main').count(), 1);
    // h1, then each group's h2, then its cards' h3: no level skipped or repeated.
    const levels = await page.$$eval('h1, h2, h3, h4', (hs) => hs.filter((h) => h.offsetParent).map((h) => Number(h.tagName[1])));
    assert.equal(levels[0], 1);
    levels.forEach((level, i) => assert.ok(i === 0 || level <= levels[i - 1] + 1, `heading levels ${levels.join()}`));
    assert.ok(await page.$$eval('.card[data-scene] h3', (hs) => hs.length) >= 11, 'a card\'s name is its group\'s sub-heading');
    // Each thumbnail says what it shows; each card's link is named by its scene.
    const cards = await page.$$eval('.card[data-scene]', (cs) => cs.map((c) => ({
      alt: c.querySelector('img').alt, name: c.querySelector('h3').textContent, text: c.textContent })));
    for (const { alt, name, text } of cards) {
      assert.ok(alt.includes(name), `the thumbnail of ${name} says "${alt}"`);
      assert.ok(text.includes(name));
    }
    // Every form control has a name (the upload's progress bar too).
    const unnamed = await page.$$eval('input, select, progress, button', (controls) => controls.filter((c) =>
      !c.labels?.length && !c.getAttribute('aria-label') && !c.getAttribute('aria-labelledby')).map((c) => c.outerHTML));
    assert.deepEqual(unnamed, []);
    // A phone's width scrolls down only.
    assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= innerWidth), 'the gallery scrolls sideways');
    // The keyboard: the codec, the upload's fields, then the cards, each showing its focus.
    const order = [];
    for (let i = 0; i < 6; ++i) {
      await page.keyboard.press('Tab');
      order.push(await page.evaluate(() => document.activeElement.id || document.activeElement.name || document.activeElement.dataset.scene));
    }
    assert.deepEqual(order.slice(0, 4), ['codec', 'name', 'colour', 'picture']);
    assert.ok(order[4], `Tab after the upload lands on ${order[4]}`);
    while (!(await page.evaluate(() => document.activeElement.classList.contains('card')))) await page.keyboard.press('Tab');
    const outline = await page.evaluate(() => getComputedStyle(document.activeElement).outlineStyle);
    assert.notEqual(outline, 'none', 'a focused card shows no focus');
    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: `${shots}/a11y-gallery-phone.png` });
    await context.close();
  });
});

test('the viewer by keyboard: tab order, the help dialog, orbit, zoom, and moving the light and the object', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
    const page = await context.newPage();
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, live, 60, 'live');
    assert.equal(await page.locator('header#hud').count(), 1);
    assert.equal(await page.locator('main canvas[role=img][aria-label]').count(), 1, 'the 3D view has no text alternative');
    assert.equal(await page.getAttribute('.lil-gui.lil-root', 'aria-label'), 'Settings');
    // Tab goes through the header, the toolbar, then the panel.
    const order = [];
    for (let i = 0; i < 9; ++i) {
      await page.keyboard.press('Tab');
      order.push(await page.evaluate(focused));
    }
    assert.deepEqual(order, ['Gallery', 'share', 'fullscreen', 'help-button', 'none', 'light', 'move', 'rotate', 'Caustic']);

    // The help: opened from its button by Enter, it takes the focus; Escape
    // closes it, gives the focus back, and leaves the mode as it was.
    await page.keyboard.press('l');
    await page.focus('#help-button');
    await page.keyboard.press('Enter');
    assert.equal(await page.getAttribute('#help-button', 'aria-expanded'), 'true');
    assert.equal(await page.evaluate(() => document.activeElement.id), 'help');
    await page.keyboard.press('Escape');
    assert.ok(await page.locator('#help').isHidden());
    assert.equal(await page.evaluate(() => document.activeElement.id), 'help-button');
    assert.equal(await page.evaluate(() => window.caustic.mode), 'light', 'Escape closing the help also changed the mode');
    // Its Close button does the same for a pointer or a finger.
    await page.keyboard.press('Space');
    assert.ok(await page.locator('#help').isVisible());
    await page.click('#help-close');
    assert.ok(await page.locator('#help').isHidden());

    // Light mode: an arrow moves the light's marker, and the server turns the light.
    await page.evaluate(() => document.activeElement.blur());
    const light = await page.evaluate(() => ({ direction: window.caustic.params.light.direction, version: window.caustic.version }));
    await page.keyboard.press('ArrowRight');
    await page.keyboard.press('ArrowRight');
    await until(page, (v) => window.caustic.version > v, 30, 'the light moved by keys', light.version);
    assert.notDeepEqual(await page.evaluate(() => window.caustic.params.light.direction), light.direction);
    // Move mode: Page Up raises the object; rotate mode: an arrow turns it.
    await page.keyboard.press('t');
    const object = await page.evaluate(() => ({ ...window.caustic.params.object, version: window.caustic.version }));
    await page.keyboard.press('PageUp');
    await until(page, (v) => window.caustic.version > v, 30, 'the object moved by keys', object.version);
    assert.notDeepEqual(await page.evaluate(() => window.caustic.params.object.position), object.position);
    await page.keyboard.press('r');
    const turned = await page.evaluate(() => window.caustic.version);
    await page.keyboard.press('ArrowLeft');
    await until(page, (v) => window.caustic.version > v, 30, 'the object turned by keys', turned);
    assert.notDeepEqual(await page.evaluate(() => window.caustic.params.object.rotation_deg), object.rotation_deg);

    // Orbit mode: the arrows turn the view (the address follows it), + and - zoom.
    await page.keyboard.press('0');
    const view = () => new URL(location.href).searchParams.get('view');
    const before = await page.evaluate(view);
    await page.keyboard.press('ArrowLeft');
    await page.keyboard.press('ArrowUp');
    assert.notEqual(await page.evaluate(view), before, 'the arrows did not turn the view');
    const far = await page.evaluate(() => window.caustic.cameraDistance());
    await page.keyboard.press('+');
    const near = await page.evaluate(() => window.caustic.cameraDistance());
    assert.ok(near < far, `+ left the camera at ${near} from ${far}`);
    await page.keyboard.press('-');
    assert.ok(await page.evaluate(() => window.caustic.cameraDistance()) > near, '- did not zoom out');
    // Keys pressed in the panel's fields are the field's, not the view's.
    const stay = await page.evaluate(view);
    await page.locator('.lil-gui .lil-controller', { hasText: 'gamma' }).locator('input').focus();
    await page.keyboard.press('ArrowLeft');
    assert.equal(await page.evaluate(view), stay);
    await context.close();
  });
});

test('Shift with an arrow or Page Up takes a fine step: a fifth of the turn of the view and of the move', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, live, 60, 'live');
    // The camera turns about the vertical through its target, at the same
    // distance from it: the chords of a 5 and a 1 degree turn stand as
    // sin(2.5 deg) to sin(0.5 deg), 4.998.
    const chord = async (key) => {
      const from = await page.evaluate(() => window.caustic.cameraPosition());
      await page.keyboard.press(key);
      const to = await page.evaluate(() => window.caustic.cameraPosition());
      return Math.hypot(...to.map((v, i) => v - from[i]));
    };
    const [step, fine] = [await chord('ArrowLeft'), await chord('Shift+ArrowLeft')];
    assert.ok(Math.abs(step / fine - 4.998) < 0.05, `a step turns the view ${step}, a fine one ${fine}`);
    // Move mode: Page Up raises the object by 3 % of the camera's distance, Shift+Page Up by a fifth of that.
    await page.keyboard.press('t');
    const rise = async (key) => {
      const from = await page.evaluate(() => ({ y: window.caustic.params.object.position[1], version: window.caustic.version }));
      await page.keyboard.press(key);
      await until(page, (v) => window.caustic.version > v, 30, `the object moved by ${key}`, from.version);
      return (await page.evaluate(() => window.caustic.params.object.position[1])) - from.y;
    };
    const [up, fineUp] = [await rise('PageUp'), await rise('Shift+PageUp')];
    assert.ok(up > 0 && Math.abs(up / fineUp - 5) < 0.05, `Page Up raised the object ${up}, Shift+Page Up ${fineUp}`);
    await page.close();
  });
});

test('Share says what it did: "Link copied" read out, or the link selected in a labelled field, never a prompt',
     async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    await context.grantPermissions(['clipboard-read', 'clipboard-write']);
    const page = await context.newPage();
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, live, 60, 'live');
    await page.click('#share');
    await until(page, () => document.getElementById('share-said')?.textContent, 10, 'the copy said');
    assert.equal(await page.getAttribute('#share-said', 'role'), 'status');
    assert.equal(await page.textContent('#share-said'), 'Link copied');
    assert.equal(await page.evaluate(() => navigator.clipboard.readText()), await page.evaluate(() => location.href));

    // A browser that lets the page copy nothing.
    const bare = await context.newPage();
    const dialogs = [];
    bare.on('dialog', (dialog) => { dialogs.push(dialog.type()); dialog.dismiss(); });
    await bare.addInitScript(() => Object.defineProperty(Navigator.prototype, 'clipboard', { get: () => undefined }));
    await bare.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(bare, live, 60, 'live');
    await bare.keyboard.press('l');
    await bare.click('#share');
    await until(bare, () => document.getElementById('share-panel')?.hidden === false, 10, 'the link shown');
    assert.deepEqual(dialogs, [], 'the link came in a prompt');
    const field = await bare.evaluate(() => {
      const f = document.activeElement;
      const r = f.getBoundingClientRect();
      return { id: f.id, readOnly: f.readOnly, label: f.labels?.[0]?.textContent, value: f.value, href: location.href,
               selected: f.value?.slice(f.selectionStart, f.selectionEnd),
               onTop: document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2) === f };
    });
    assert.deepEqual(field, { id: 'share-url', readOnly: true, label: 'Link to this view', value: field.href,
                              href: field.href, selected: field.href, onTop: true });
    assert.match(await bare.textContent('#share-said'), /selected in the field/);
    // Escape puts the field away and the focus back on Share, the mode as it was.
    await bare.keyboard.press('Escape');
    assert.ok(await bare.locator('#share-panel').isHidden());
    assert.equal(await bare.evaluate(() => document.activeElement.id), 'share');
    assert.equal(await bare.evaluate(() => window.caustic.mode), 'light');
    await context.close();
  });
});

test('on a pool, D drops a stone where the middle of the view meets the water', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    await page.goto(`${server.url}/viewer.html?scene=pool&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.water?.updates >= 1, 90, 'the water drawn');
    const answered = page.waitForResponse((r) => r.url().endsWith('/drops'), { timeout: 30000 });
    await page.keyboard.press('d');
    const response = await answered;
    assert.equal(response.status(), 202);
    await page.close();
  });
});

test('the viewer seen: contrast over the picture, a pressed mode not by colour alone, a phone, large text, less motion',
     async () => {
  await withServer(async (server) => {
    const context = await browser.newContext({ viewport: { width: 360, height: 640 }, isMobile: true, hasTouch: true });
    const page = await context.newPage();
    await page.emulateMedia({ reducedMotion: 'reduce' });
    await page.goto(`${server.url}/viewer.html?scene=wavy&codec=vp8`);
    await until(page, live, 60, 'live');
    // The header's words against its background laid over white (the
    // brightest picture under it), each state's colour: 4.5:1 at least.
    const ratios = await page.evaluate(() => {
      const rgb = (text) => text.match(/[\d.]+/g).map(Number);
      const lum = ([r, g, b]) => [r, g, b].map((c) => { c /= 255; return c <= 0.03928 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4; })
        .reduce((s, c, i) => s + c * [0.2126, 0.7152, 0.0722][i], 0);
      const [r, g, b, a = 1] = rgb(getComputedStyle(document.getElementById('hud')).backgroundColor);
      const back = [r, g, b].map((c) => c * a + 255 * (1 - a));
      const label = document.getElementById('state');
      const out = {};
      for (const state of ['connecting', 'live', 'reconnecting', 'full', 'error']) {
        label.dataset.state = state;
        const [l1, l2] = [lum(rgb(getComputedStyle(label).color)), lum(back)];
        out[state] = (Math.max(l1, l2) + 0.05) / (Math.min(l1, l2) + 0.05);
      }
      label.dataset.state = window.caustic.connection;
      return out;
    });
    for (const [state, ratio] of Object.entries(ratios)) assert.ok(ratio >= 4.5, `"${state}" at ${ratio.toFixed(2)}:1`);
    // The panel's widgets have an edge of 3:1 against the panel.
    const edges = await page.evaluate(() => {
      const lum = (text) => text.match(/[\d.]+/g).slice(0, 3).map(Number)
        .map((c) => { c /= 255; return c <= 0.03928 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4; })
        .reduce((s, c, i) => s + c * [0.2126, 0.7152, 0.0722][i], 0);
      const panel = lum(getComputedStyle(document.querySelector('.lil-gui.lil-root')).backgroundColor);
      return ['.lil-slider', '.lil-number input', '.lil-option .lil-display', 'input[type=checkbox]', '.lil-controller button']
        .map((selector) => {
          const shadow = getComputedStyle(document.querySelector(`.lil-gui ${selector}`)).boxShadow;
          const edge = shadow === 'none' ? panel : lum(shadow);
          return [selector, (Math.max(edge, panel) + 0.05) / (Math.min(edge, panel) + 0.05)];
        });
    });
    for (const [selector, ratio] of edges) assert.ok(ratio >= 3, `the panel's ${selector} at ${ratio.toFixed(2)}:1`);
    const pressed = await page.$eval('#modes [aria-pressed="true"]', (b) => getComputedStyle(b).boxShadow);
    assert.notEqual(pressed, 'none', 'the pressed mode differs by its colour only');

    // A phone: no sideways scroll, the folded panel clear of the toolbar,
    // the help inside the screen (scrolling within itself).
    assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= innerWidth));
    assert.ok(!(await page.evaluate(overlap, ['.lil-gui.lil-root', '#modes'])), 'the folded panel lies over the toolbar');
    assert.deepEqual(await page.evaluate(smallTargets), [], 'header targets under 24x24 px');
    // Less motion: folding the panel (lil-gui's transition class) does not slide.
    const slide = await page.$eval('.lil-gui.lil-root', (root) => {
      root.classList.add('lil-transition');
      const seconds = parseFloat(getComputedStyle(root.querySelector('.lil-children')).transitionDuration);
      root.classList.remove('lil-transition');
      return seconds;
    });
    assert.ok(slide <= 0.01, `the panel slides for ${slide} s`);
    await page.tap('#help-button');
    const help = await page.$eval('#help', (h) => ({
      bottom: h.getBoundingClientRect().bottom,
      scrolls: h.scrollHeight <= h.clientHeight || ['auto', 'scroll'].includes(getComputedStyle(h).overflowY) }));
    assert.ok(help.bottom <= 640 && help.scrolls, `the help ends at ${help.bottom} px on a 640 px screen`);
    mkdirSync(shots, { recursive: true });
    await page.screenshot({ path: `${shots}/a11y-viewer-phone-help.png` });
    await page.tap('#help-close');

    // Text at twice its size on a laptop (the page zoomed to 200 %: a
    // 1280 px window is 640 CSS pixels): the header wraps, and neither the
    // panel nor the warnings lie over its words.
    await page.setViewportSize({ width: 800, height: 500 });
    await page.evaluate(() => { document.documentElement.style.fontSize = '200%'; });
    await until(page, () => {
      const [header, panel] = ['#hud', '.lil-gui.lil-root'].map((e) => document.querySelector(e).getBoundingClientRect());
      return header.bottom <= panel.top;
    }, 10, 'the panel below the header');
    await page.screenshot({ path: `${shots}/a11y-viewer-large-text.png` });
    await context.close();
  });
});

test('the broadcast page: landmarks, a named picture, and a state line that says why it waits', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    // A broadcast server that is not there: the page waits and says so.
    await page.goto(`${server.url}/watch.html#scene=slab&janus=/nothing&mountpoint=1`);
    await until(page, () => window.caustic.connection === 'reconnecting', 30, 'the wait said');
    assert.equal(await page.locator('header#hud').count(), 1);
    assert.equal(await page.locator('main#stage').count(), 1);
    assert.ok(await page.getAttribute('#video', 'aria-label'), 'the broadcast\'s video has no name');
    assert.match(await page.evaluate(`(${readable})('#state')`), /^reconnecting: /);
    assert.deepEqual(await page.evaluate(smallTargets), [], 'header targets under 24x24 px');
    // "video only" is a button: Space (which a link ignores) reloads the page
    // in that view, and Enter brings the room back.
    assert.equal(await page.$eval('#view-toggle', (t) => t.tagName), 'BUTTON');
    for (const [key, view, label] of [['Space', 'video', '3D room'], ['Enter', 'room', 'video only']]) {
      await page.focus('#view-toggle');
      await Promise.all([page.waitForEvent('load', { timeout: 30000 }), page.keyboard.press(key)]);
      await until(page, (v) => window.caustic?.view === v, 10, `the ${view} view`, view);
      assert.equal(await page.textContent('#view-toggle'), label);
    }
    await page.close();
  });
});

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

test('a retry is read once, its state with its reason: not the state again at each try, then the reason', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    let tries = 0;
    await page.route('**/api/v1/sessions', (route) => {
      if (route.request().method() !== 'POST') return route.continue();
      tries += 1;
      return route.abort();
    });
    await page.addInitScript(recordStateReads);
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    // Three tries (0.25-0.5 s, then 0.5-1 s apart), and the third's failure said.
    for (let waited = 0; tries < 3 && waited < 60000; waited += 100) await page.waitForTimeout(100);
    assert.ok(tries >= 3, `${tries} tries in a minute`);
    await until(page, () => /retrying in/.test(document.getElementById('state').textContent), 30, 'the third failure');
    assert.deepEqual(await page.evaluate(() => window.stateReads), ['connecting', 'reconnecting: the server does not answer']);
    await page.close();
  });
});

test('no WebGL, no WebRTC and no server are said in words, with nothing left counting', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const noGl = await context.newPage();
    await noGl.addInitScript(() => {
      const getContext = HTMLCanvasElement.prototype.getContext;
      HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
        return /webgl/.test(kind) ? null : getContext.call(this, kind, ...rest);
      };
    });
    await noGl.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(noGl, () => window.caustic.connection === 'error', 30, 'the error');
    assert.match(await noGl.textContent('#state'), /cannot draw the 3D view \(WebGL/);
    assert.ok(await noGl.locator('#loading').isHidden(), 'the loading steps go on counting after the error');

    const noRtc = await context.newPage();
    await noRtc.addInitScript(() => { delete window.RTCPeerConnection; });
    await noRtc.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(noRtc, () => window.caustic.connection === 'error', 30, 'the error');
    assert.match(await noRtc.textContent('#state'), /cannot receive the video stream \(it has no WebRTC/);
    assert.ok(await noRtc.locator('#loading').isHidden());

    // A gallery whose server does not answer says so, and what to do.
    const down = await context.newPage();
    await down.route('**/api/v1/scenes', (route) => route.abort());
    await down.goto(`${server.url}/`);
    await until(down, () => /Cannot load/.test(document.getElementById('gallery-status').textContent), 20, 'the failure');
    assert.match(await down.textContent('#gallery-status'), /the server does not answer\. Reload the page/);
    await context.close();
  });
});
