// SPDX-License-Identifier: LGPL-2.1-or-later
// The pages' wait before trying again: a jittered backoff, bounded, and a
// server's Retry-After believed up to its cap.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { webModule } from './web_module.mjs';

const { BACKOFF_MAX_MS, RETRY_AFTER_MAX_MS, retryAfterMs, retryDelay, transient } = await webModule('retry.js');

test('the backoff doubles from 0.5 s to 10 s, each wait between half and all of its step', () => {
  const steps = [500, 1000, 2000, 4000, 8000, 10000, 10000];
  steps.forEach((step, attempt) => {
    assert.equal(retryDelay(attempt, null, () => 0), step / 2);
    assert.ok(Math.abs(retryDelay(attempt, null, () => 0.999999) - step) < 1e-2);
  });
  assert.equal(retryDelay(1e6, null, () => 0.999999) <= BACKOFF_MAX_MS, true);
});

test('pages cut off together do not come back together', () => {
  const waits = new Set(Array.from({ length: 20 }, () => Math.round(retryDelay(3))));
  assert.ok(waits.size > 10, `20 pages drew only ${waits.size} different waits`);
});

test('a server that names a longer wait is believed, up to a minute', () => {
  assert.equal(retryDelay(0, 5000, () => 0.5), 5000);
  assert.equal(retryDelay(4, 1000, () => 0), 4000);  // the backoff is longer
  assert.equal(retryDelay(0, 3600 * 1000, () => 0), RETRY_AFTER_MAX_MS);
});

test('Retry-After is read as seconds or a date, and nothing else', () => {
  assert.equal(retryAfterMs('2'), 2000);
  assert.equal(retryAfterMs(' 10 '), 10000);
  assert.equal(retryAfterMs('86400'), RETRY_AFTER_MAX_MS);
  const now = Date.parse('Sun, 06 Dec 2026 12:00:00 GMT');
  assert.equal(retryAfterMs('Sun, 06 Dec 2026 12:00:07 GMT', now), 7000);
  assert.equal(retryAfterMs('Sun, 06 Dec 2026 11:00:00 GMT', now), 0);
  for (const bad of [null, undefined, '', 'soon', '-1', '1.5']) assert.equal(retryAfterMs(bad), null, String(bad));
});

test('asking again is worth it after a timeout, a 429 or any 5xx, and after no other refusal', () => {
  for (const status of [408, 429, 500, 502, 503, 504]) assert.equal(transient(status), true, String(status));
  for (const status of [400, 401, 403, 404, 409, 413, 415, 422]) assert.equal(transient(status), false, String(status));
});
