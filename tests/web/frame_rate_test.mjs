// SPDX-License-Identifier: LGPL-2.1-or-later
// The frame rate that picks the viewer's room quality, fed synthetic frame
// times: what a loading page, a tab coming back and a stall must not count
// as, and what a page slow all along must still be measured as.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { webModule } from './web_module.mjs';

const { FrameRate, GAP_MS, WINDOW_MS } = await webModule('frame_rate.js');

// Ticks a frame every `interval` ms from `from` for `ms`; the rates reported.
function run(rate, from, interval, ms) {
  const reported = [];
  for (let t = from; t <= from + ms; t += interval) {
    const fps = rate.tick(t);
    if (fps !== null) reported.push(fps);
  }
  return reported;
}

test('a steady page is measured once a window of two seconds closes', () => {
  const rate = new FrameRate();
  const reported = run(rate, 0, 1000 / 60, WINDOW_MS * 3 + 50);
  assert.equal(reported.length, 3);
  for (const fps of reported) assert.ok(Math.abs(fps - 60) < 1, `${fps}`);
  assert.equal(rate.fps, reported.at(-1));
});

test('a slow page is measured as slow', () => {
  const reported = run(new FrameRate(), 0, 50, WINDOW_MS * 2);
  assert.ok(reported.length >= 1 && reported.every((fps) => Math.abs(fps - 20) < 0.5), `${reported}`);
});

test('frames before a reset (the page loading, a hidden tab) do not count', () => {
  const rate = new FrameRate();
  // Loading: a frame a second for 1.9 s, then the room is made.
  for (const t of [0, 900, 1800]) rate.tick(t);
  rate.reset();
  const reported = run(rate, 1900, 1000 / 60, WINDOW_MS + 100);
  assert.equal(reported.length, 1);
  assert.ok(reported[0] > 59, `the load counted: ${reported[0]} fps`);
});

test('a lone long gap between frames starts the window again', () => {
  const rate = new FrameRate();
  const fast = run(rate, 0, 10, 1500);  // 100 fps, the window not yet closed
  assert.deepEqual(fast, []);
  // The tab was hidden for a minute (no frames), or a shader compiled.
  const after = run(rate, 1500 + 60000, 10, WINDOW_MS + 50);
  assert.equal(after.length, 1);
  assert.ok(after[0] > 99, `the gap counted: ${after[0]} fps`);
});

test('gap after gap is the page\'s rate, not a stall', () => {
  const rate = new FrameRate();
  const reported = run(rate, 0, GAP_MS * 2, GAP_MS * 2 * 8);
  assert.ok(reported.length >= 1, 'a page drawing a frame every two seconds was never measured');
  assert.ok(reported.every((fps) => fps < 1), `${reported}`);
});

test('a window needs frames inside it: the first frame only starts it', () => {
  const rate = new FrameRate();
  assert.equal(rate.tick(0), null);
  assert.equal(rate.tick(WINDOW_MS / 2), null);
  assert.equal(rate.fps, null);
});
