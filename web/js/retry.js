// SPDX-License-Identifier: LGPL-2.1-or-later
// The wait before trying to connect again, shared by the viewer and the
// broadcast page: 0.5 s after the first failure, doubling to 10 s, so that
// a server restarting is found within seconds and a server down for long
// is asked once every 10 s per page, not hammered; counted down on the
// page so that a visitor sees something is happening.

/// Calls onSecondsLeft(n) each second while waiting, then onDue(), after
/// the wait for try number `attempt` (0 for the first retry). Returns a
/// function that cancels the wait (a newer retry takes its place).
export function retryAfter(attempt, onSecondsLeft, onDue) {
  const due = performance.now() + Math.min(10000, 500 * 2 ** attempt);
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
