// SPDX-License-Identifier: LGPL-2.1-or-later
// How the viewer meets a server or a network that lets it down, in Debian's
// chromium against a real `causticd serve` on 127.0.0.1: a full server, an
// unknown scene, a restart, a lost network, a video path that never opens
// and one that opens and carries no picture. Each says what happened and,
// where trying again can help, comes back live. Every wait is bounded.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import { launchChromium } from './chromium.mjs';
import { startServer, stopServer, until, withServer } from './harness.mjs';
import { holdsPort, quietPort } from './ports.mjs';

let browser;
before(async () => {
  browser = await launchChromium();
});
after(async () => { await browser?.close(); });

/// The page's signalling relayed through `edit(message, toServer)`, which
/// returns what goes on (the message, changed or not) or null to drop it.
function relaySignalling(page, edit) {
  return page.routeWebSocket(() => true, (ws) => {
    const server = ws.connectToServer();
    const pass = (to, toServer) => (m) => {
      const out = edit(m, toServer);
      if (out !== null) to.send(out);
    };
    ws.onMessage(pass(server, true));
    server.onMessage(pass(ws, false));
  });
}

test('a full server is shown as such and the page recovers when a place frees up', async () => {
  await withServer(['--max-sessions', '1'], async (server) => {
    const first = await browser.newPage();
    await first.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(first, () => window.caustic.connection === 'live', 30, 'the first viewer live');
    const second = await browser.newPage();
    await second.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(second, () => window.caustic.connection === 'full', 20, 'the second viewer told the server is full');
    await first.close({ runBeforeUnload: true });  // its pagehide deletes its session
    await until(second, () => window.caustic.connection === 'live', 40, 'the second viewer live after retrying');
    await second.close();
  });
});

test('an unknown scene is a permanent error: the page says what to do and does not ask again', async () => {
  await withServer(async (server) => {
    const page = await browser.newPage();
    let creates = 0;
    page.on('request', (r) => { if (r.method() === 'POST' && r.url().endsWith('/api/v1/sessions')) creates += 1; });
    await page.goto(`${server.url}/viewer.html?scene=no-such-scene&codec=vp8`);
    await until(page, () => window.caustic.connection === 'error', 20, 'the error shown');
    assert.match(await page.textContent('#state'), /Pick a scene in the gallery/);
    await page.waitForTimeout(3000);
    assert.equal(creates, 1, 'the page asked again for a scene that does not exist');
    assert.equal(await page.evaluate(() => window.caustic.connection), 'error');
    await page.close();
  });
});

test('a server restart shows reconnecting and the page comes back live', async () => {
  // It comes back on the port it had: one that no other process takes by
  // chance while it is down (ports.mjs). A first start on a port taken
  // before it bound it is tried again on another, three times in all.
  let server;
  for (let attempt = 0; !server; attempt += 1) {
    try {
      server = await startServer(['--port', `${await quietPort()}`]);
    } catch (e) {
      if (attempt === 2) throw e;
    }
  }
  const port = new URL(server.url).port;
  try {
    const page = await browser.newPage();
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'live');
    await stopServer(server);
    await until(page, () => ['reconnecting', 'error'].includes(window.caustic.connection), 20, 'the loss noticed');
    // A transient failure says so and counts down to the next try.
    await until(page, () => /the server does not answer; retrying in \d+ s/.test(document.getElementById('state').textContent),
                30, 'the countdown to the next try');
    server = await startServer(['--port', port]);
    assert.ok(holdsPort(server.pid, Number(port)), `the restarted server is not alone on port ${port}`);
    await until(page, () => window.caustic.connection === 'live', 60, 'live again after the restart');
    await page.close();
  } finally {
    await stopServer(server);
  }
});

test('a lost network shows reconnecting and the page recovers', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'live');
    await page.evaluate(() => window.caustic.dropSignalling());  // what a dead network does to the socket
    await context.setOffline(true);
    await until(page, () => ['reconnecting', 'error'].includes(window.caustic.connection), 20, 'the loss noticed');
    await page.waitForTimeout(1500);
    await context.setOffline(false);
    await until(page, () => window.caustic.connection === 'live', 60, 'live again');
    await context.close();
  });
});

test('a viewer that hangs its peer connection up has disconnected, not broken the pipeline', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    const byes = [];
    await relaySignalling(page, (m, toServer) => {
      const message = JSON.parse(m);
      if (!toServer && message.type === 'bye') byes.push(message.reason);
      return m;
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'live');
    await page.evaluate(() => window.caustic.closePeer());
    // Every browser hang-up was once a "pipeline error", logged and counted as one.
    for (let i = 0; i < 100 && byes.length === 0; ++i) await page.waitForTimeout(200);
    assert.deepEqual(byes, ['peer disconnected']);
    const metrics = await (await fetch(`${server.url}/metrics`)).text();
    assert.match(metrics, /^causticd_pipeline_errors_total 0$/m);
    await context.close();
  });
});

test('a browser the video cannot reach says so, keeps trying, and goes live once the path opens', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    // Signalling passes but no ICE candidate does, either way: what a
    // firewall that drops WebRTC's UDP leaves of a session.
    let blocked = true;
    await relaySignalling(page, (m) => (blocked && JSON.parse(m).type === 'ice' ? null : m));
    const said = [];
    await page.exposeFunction('noteState', (text) => said.push(text));
    await page.addInitScript(() => {
      new MutationObserver(() => window.noteState(document.getElementById('state').textContent))
        .observe(document, { subtree: true, childList: true, characterData: true });
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => /^reconnecting: the video could not reach this browser.*retrying in \d+ s/
      .test(document.getElementById('state').textContent), 45, 'the unreachable video named, with a retry');
    assert.ok(!said.some((s) => /connection was lost/.test(s)), `a path that never opened was called lost: ${said}`);
    blocked = false;
    await until(page, () => window.caustic.connection === 'live', 60, 'live once candidates pass');
    await context.close();
  });
});

test('a path that connects but carries no picture says so instead of staying live over an empty stage', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    // The server's offer turned inactive on the way, and the browser's
    // answer turned back to recvonly (the server refuses an inactive one):
    // the path connects (its data channel) and the browser takes no video,
    // as with a codec it cannot decode or a middlebox that drops the media.
    let starved = true;
    await relaySignalling(page, (m, toServer) => {
      const message = JSON.parse(m);
      if (!starved) return m;
      if (!toServer && message.type === 'offer')
        return JSON.stringify({ ...message, sdp: message.sdp.replace(/a=sendonly/g, 'a=inactive') });
      if (toServer && message.type === 'answer')
        return JSON.stringify({ ...message, sdp: message.sdp.replace(/a=inactive/g, 'a=recvonly') });
      return m;
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 30, 'live without a picture');
    assert.equal(await page.evaluate(() => window.caustic.framesShown), 0);
    await until(page, () => /^reconnecting: connected, but no picture came: this browser may not decode VP8/
      .test(document.getElementById('state').textContent), 45, 'the missing picture named');
    starved = false;
    await until(page, () => window.caustic.connection === 'live' && window.caustic.framesShown > 0, 60,
                'pictures once the offer passes whole');
    await context.close();
  });
});

test('a stream that ends as soon as it is live is asked for again ever more slowly, not every half second', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    const posts = [];  // when each POST /sessions left the page
    page.on('request', (r) => {
      if (r.method() === 'POST' && r.url().endsWith('/api/v1/sessions')) posts.push(Date.now());
    });
    const sockets = [];
    await page.routeWebSocket(() => true, (ws) => {
      const upstream = ws.connectToServer();
      ws.onMessage((m) => upstream.send(m));
      upstream.onMessage((m) => ws.send(m));
      sockets.push(ws);
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    // Each stream, once live, is ended at once, as a server that drops it would.
    const byes = [];
    const retried = () => byes.map((at) => posts.find((p) => p > at)).filter(Boolean).length;
    for (const start = Date.now(); retried() < 3 && Date.now() - start < 60000;) {
      if (sockets.length > byes.length && await page.evaluate(() => window.caustic.connection === 'live')) {
        sockets.at(-1).send(JSON.stringify({ type: 'bye', reason: 'ended by the test' }));
        byes.push(Date.now());
      }
      await page.waitForTimeout(100);
    }
    const waits = byes.map((at) => (posts.find((p) => p > at) ?? NaN) - at);
    assert.ok(retried() >= 3, `only ${retried()} retries in a minute (waits ${waits})`);
    // 0.25-0.5 s, 0.5-1 s, 1-2 s: the third retry waits a second at least.
    assert.ok(waits[2] >= 900, `the retries after a live stream ended waited ${waits} ms: the backoff started over`);
    await context.close();
  });
});

test('an offer the browser cannot take fails the stream, which is tried again', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    let broken = true;
    await relaySignalling(page, (m, toServer) => {
      const message = JSON.parse(m);
      if (broken && !toServer && message.type === 'offer') return JSON.stringify({ ...message, sdp: 'not a description' });
      return m;
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => /^reconnecting: the video could not be set up/.test(document.getElementById('state').textContent),
                30, 'the failed offer named');
    broken = false;
    await until(page, () => window.caustic.connection === 'live', 60, 'live once the offer passes');
    await context.close();
  });
});

test('a proxy\'s HTML error page and a Retry-After are read as such when a session is asked for', async () => {
  await withServer(async (server) => {
    const context = await browser.newContext();
    const page = await context.newPage();
    const posts = [];
    await page.route('**/api/v1/sessions', (route) => {
      if (route.request().method() !== 'POST') return route.continue();
      posts.push(Date.now());
      if (posts.length === 1) return route.fulfill({ status: 502, contentType: 'text/html', body: '<html>Bad Gateway</html>' });
      if (posts.length === 2) {
        return route.fulfill({ status: 429, headers: { 'Retry-After': '3' }, contentType: 'application/problem+json',
                               body: JSON.stringify({ status: 429, detail: 'this address holds 4 sessions' }) });
      }
      return route.continue();
    });
    const said = [];
    await page.exposeFunction('noteState', (text) => said.push(text));
    await page.addInitScript(() => {
      new MutationObserver(() => window.noteState(document.getElementById('state')?.textContent))
        .observe(document, { subtree: true, childList: true, characterData: true });
    });
    await page.goto(`${server.url}/viewer.html?scene=slab&codec=vp8`);
    await until(page, () => window.caustic.connection === 'live', 60, 'live after the refusals');
    assert.ok(said.some((s) => /^reconnecting: the server answered 502; retrying/.test(s)), said.join('\n'));
    assert.ok(said.some((s) => /this address holds 4 sessions; retrying in 3 s/.test(s)), said.join('\n'));
    assert.ok(posts[2] - posts[1] >= 2900, `asked again ${posts[2] - posts[1]} ms after a Retry-After of 3 s`);
    await context.close();
  });
});
