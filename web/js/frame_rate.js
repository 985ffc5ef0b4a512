// SPDX-License-Identifier: LGPL-2.1-or-later
// The page's frame rate, which picks the room's quality. Only time the page
// spends drawing counts: a window starts afresh when the room is made (the
// load before it drew nothing), when a hidden tab comes back (the browser
// drew nothing while hidden) and after a lone long gap between two frames
// (a shader compiled, a stall), each of which would otherwise read as a
// slow page and drop the quality for good. A page that is slow all along
// shows gap after gap: from the third in a row they are its rate.

export const WINDOW_MS = 2000;
export const GAP_MS = 1000;
export const STEADY_GAPS = 3;

/// Frames per second over windows of about two seconds.
export class FrameRate {
  constructor() {
    this.fps = null;
    this.reset();
  }

  /// Forgets the window under way: the next frame starts one.
  reset() {
    this.since = null;
    this.last = null;
    this.frames = 0;
    this.gaps = 0;
  }

  /// Counts a frame drawn at `now` (ms); returns the rate when a window
  /// closes, else null.
  tick(now) {
    const gap = this.last !== null && now - this.last > GAP_MS;
    this.last = now;
    this.gaps = gap ? this.gaps + 1 : 0;
    if (this.since === null || (gap && this.gaps < STEADY_GAPS)) {
      this.since = now;
      this.frames = 0;
      return null;
    }
    ++this.frames;
    if (now - this.since < WINDOW_MS) return null;
    this.fps = (1000 * this.frames) / (now - this.since);
    this.frames = 0;
    this.since = now;
    return this.fps;
  }
}
