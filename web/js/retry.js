// SPDX-License-Identifier: LGPL-2.1-or-later
// The wait before trying again, shared by the viewer, its parameter patches
// and the broadcast page: about 0.5 s after the first failure, doubling to
// 10 s, so that a server restarting is found within seconds and a server
// down for long is asked once every 10 s per page, not hammered; counted
// down on the page so that a visitor sees something is happening. Each
// wait is drawn between half and all of its step, so that the pages a
// restart cut off do not all come back in the same instant. A server that
// says when to come back (Retry-After) is believed, up to a minute.

export const BACKOFF_MAX_MS = 10000;
export const RETRY_AFTER_MAX_MS = 60000;

/// Whether asking again may get another answer than `status`: a timeout,
/// too many requests, or a server (or the proxy before it) failing or
/// between restarts. Any other 4xx is a refusal that asking again repeats.
export const transient = (status) => status === 408 || status === 429 || status >= 500;

/// The wait (ms) before try number `attempt` (0 for the first retry): the
/// backoff with its jitter (`random` in [0, 1)), or what the server asked
/// for (`serverMs`, null when it named none) if that is longer, capped.
export function retryDelay(attempt, serverMs = null, random = Math.random) {
  const step = Math.min(BACKOFF_MAX_MS, 500 * 2 ** Math.min(attempt, 16));
  const backoff = step * (0.5 + 0.5 * random());
  return Math.min(RETRY_AFTER_MAX_MS, Math.max(backoff, serverMs ?? 0));
}

/// A Retry-After header's wait in ms (seconds or an HTTP date), or null
/// when there is none or it cannot be read.
export function retryAfterMs(header, nowMs = Date.now()) {
  if (header === null || header === undefined) return null;
  const text = String(header).trim();
  if (/^[0-9]+$/.test(text)) return Math.min(RETRY_AFTER_MAX_MS, Number(text) * 1000);
  const at = /[a-z]/i.test(text) ? Date.parse(text) : NaN;  // a date names its day; Date.parse takes "-1" as a year
  return Number.isNaN(at) ? null : Math.min(RETRY_AFTER_MAX_MS, Math.max(0, at - nowMs));
}

/// Calls onSecondsLeft(n) each second while waiting, then onDue(), after
/// the wait for try number `attempt` (retryDelay, with the server's
/// `serverMs` if it named one). Returns a function that cancels the wait
/// (a newer retry takes its place).
export function retryAfter(attempt, onSecondsLeft, onDue, serverMs = null) {
  const due = performance.now() + retryDelay(attempt, serverMs);
  let timer = null;
  const tick = () => {
    const left = Math.ceil((due - performance.now()) / 1000);
    if (left <= 0) return onDue();
    onSecondsLeft(left);
    timer = setTimeout(tick, Math.min(1000, due - performance.now()));
  };
  tick();
  return () => clearTimeout(timer);
}
