// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's parameter channel against a stubbed fetch: a patch the
// server cannot take now goes again after its Retry-After, merged under
// the changes made meanwhile; a refusal and a patch tried too often are
// given up and said; an answer that is not JSON is named by its status;
// a restored section and a change to it after go in order, not merged.
import assert from 'node:assert/strict';
import { afterEach, beforeEach, mock, test } from 'node:test';

import { webModule } from './web_module.mjs';

const { ParamChannel } = await webModule('api.js');

const session = { id: 's', token: 't', url: '/api/v1/sessions/s' };
let sent, answers;

beforeEach(() => {
  sent = [];
  answers = [];
  // Node 20.11 and later take an options object, Debian 12's Node 18.19
  // (where mock timers began) an array of names: whichever this one takes.
  try {
    mock.timers.enable({ apis: ['setTimeout'] });
  } catch {
    mock.timers.enable(['setTimeout']);
  }
  globalThis.fetch = async (url, init) => {
    sent.push(JSON.parse(init.body));
    const answer = answers.shift() ?? { status: 200, body: { version: sent.length } };
    if (answer.network) throw new TypeError('Failed to fetch');
    const json = answer.type === undefined;
    return new Response(json ? JSON.stringify(answer.body ?? {}) : answer.body, {
      status: answer.status,
      headers: { 'Content-Type': json ? 'application/json' : answer.type, ...answer.headers },
    });
  };
});
afterEach(() => { mock.timers.reset(); });

// Lets the channel's promises run, then moves the clock on by `ms`.
async function pass(ms) {
  for (let i = 0; i < 20; ++i) await new Promise((resolve) => { setImmediate(resolve); });
  mock.timers.tick(ms);
  for (let i = 0; i < 20; ++i) await new Promise((resolve) => { setImmediate(resolve); });
}

function channel() {
  const said = { applied: [], errors: [], retrying: [], gaveUp: [] };
  const c = new ParamChannel(session, {
    onApplied: (body) => said.applied.push(body),
    onError: (problem) => said.errors.push(problem),
    onRetrying: (problem, ms) => said.retrying.push([problem.detail, ms]),
    onGaveUp: (problem) => said.gaveUp.push(problem),
  });
  return [c, said];
}

test('a 429 is sent again after its Retry-After, with the changes made meanwhile merged over it', async () => {
  answers.push({ status: 429, headers: { 'Retry-After': '3' }, body: { detail: 'too many requests' } });
  const [c, said] = channel();
  c.set({ post: { gamma: 2.5, bloom_strength: 0.2 } });
  c.set({ post: { bloom_strength: 0.7 } });  // while the first is in flight
  await pass(0);
  assert.deepEqual(said.retrying, [['too many requests', 3000]]);
  await pass(2900);
  assert.equal(sent.length, 1, 'sent again before the Retry-After');
  await pass(200);
  assert.deepEqual(sent, [{ post: { gamma: 2.5, bloom_strength: 0.2 } }, { post: { gamma: 2.5, bloom_strength: 0.7 } }]);
  assert.equal(said.applied.length, 1);
  assert.deepEqual([said.errors, said.gaveUp], [[], []]);
});

test('a proxy\'s HTML 502 is named by its status and tried again', async () => {
  answers.push({ status: 502, type: 'text/html', body: '<html>Bad Gateway</html>' });
  const [c, said] = channel();
  c.set({ object: { ior: 1.7 } });
  await pass(0);
  assert.equal(said.retrying[0][0], 'the server answered 502');
  await pass(1000);
  assert.equal(sent.length, 2);
  assert.equal(said.applied.length, 1);
});

test('a patch tried five times without an answer is given up, and the next change is sent', async () => {
  for (let i = 0; i < 5; ++i) answers.push({ network: true });
  const [c, said] = channel();
  c.set({ object: { ior: 1.7 } });
  for (let i = 0; i < 5; ++i) await pass(10000);
  assert.equal(sent.length, 5);
  assert.equal(said.retrying.length, 4);
  assert.equal(said.gaveUp.length, 1);
  assert.match(said.gaveUp[0].detail, /does not answer/);
  c.set({ object: { ior: 1.8 } });
  await pass(0);
  assert.deepEqual(sent.at(-1), { object: { ior: 1.8 } });
  assert.equal(said.applied.length, 1);
});

test('a refusal (422) is said once and not sent again', async () => {
  answers.push({ status: 422, body: { key: 'object.ior', detail: 'out of range' } });
  const [c, said] = channel();
  c.set({ object: { ior: 99 } });
  await pass(60000);
  assert.equal(sent.length, 1);
  assert.deepEqual(said.errors.map((p) => [p.key, p.detail, p.status]), [['object.ior', 'out of range', 422]]);
  assert.deepEqual([said.retrying, said.gaveUp], [[], []]);
});

test('a closed channel sends nothing more, even a patch waiting to go again', async () => {
  answers.push({ status: 503, headers: { 'Retry-After': '1' } });
  const [c, said] = channel();
  c.set({ object: { ior: 1.7 } });
  await pass(0);
  c.close();
  await pass(5000);
  assert.equal(sent.length, 1);
  assert.deepEqual(said.applied, []);
});

test('a section restored and then changed goes as two patches, in order', async () => {
  const [c, said] = channel();
  c.set({ post: { gamma: 2.5 } });  // in flight
  c.set({ light: null, post: null });  // Reset scene
  c.set({ light: { intensity: 3 } });  // a change at once after it
  c.set({ light: { elevation_deg: 40 } });
  await pass(0);
  assert.deepEqual(sent, [
    { post: { gamma: 2.5 } },
    { light: null, post: null },
    { light: { intensity: 3, elevation_deg: 40 } },
  ]);
  assert.equal(said.applied.length, 3);
});

test('a restore after a change replaces it, and a patch sent again keeps its restore', async () => {
  answers.push({ status: 503, headers: { 'Retry-After': '1' } });
  const [c] = channel();
  c.set({ light: null });  // refused for now
  c.set({ light: { intensity: 3 } });
  c.set({ object: { ior: 1.6 } });
  await pass(0);
  await pass(1000);
  assert.deepEqual(sent, [{ light: null }, { light: null }, { light: { intensity: 3 }, object: { ior: 1.6 } }]);
  c.set({ object: { ior: 1.5 } });  // in flight
  c.set({ post: { gamma: 1.8 } });
  c.set({ post: null });
  await pass(0);
  assert.deepEqual(sent.slice(3), [{ object: { ior: 1.5 } }, { post: null }]);
});
