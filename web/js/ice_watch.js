// SPDX-License-Identifier: LGPL-2.1-or-later
// Whether the video's path ever opened, told apart from a path that opened
// and then closed. Signalling can succeed where the media cannot: a
// firewall or VPN that drops WebRTC's UDP lets the offer and answer through
// and then leaves the peer connection "connecting" for ever (Chromium only
// gives up on a pair it has tried, and with no reachable candidate it tries
// none). A page that waited for the browser would count seconds under
// "connecting" with no end; this gives it a reason and lets it try again.

// From the answer to a connected path: well under a second over loopback
// or a LAN, a few seconds through a TURN relay; past this, nothing is coming.
export const CONNECT_TIMEOUT_MS = 15000;

export const UNREACHABLE = 'the video could not reach this browser (a firewall or VPN may block WebRTC)';
export const LOST = 'the connection was lost';

/// Watches `pc`: onLive() when its path connects, onFail(reason) when it
/// fails (UNREACHABLE if it never connected, LOST if it had) or, once
/// armed with arm() after the answer is sent, when CONNECT_TIMEOUT_MS pass
/// without a connection. `failOn` names the states that count as failed.
/// Returns { arm, stop }; stop() ends the timer (on close).
export function watchIce(pc, { onLive, onFail, failOn = ['failed'] }) {
  let connected = false;
  let timer = null;
  const stop = () => { clearTimeout(timer); timer = null; };
  pc.addEventListener('connectionstatechange', () => {
    const state = pc.connectionState;
    if (state === 'connected') {
      connected = true;
      stop();
      onLive();
    } else if (failOn.includes(state)) {
      stop();
      onFail(connected ? LOST : UNREACHABLE);
    }
  });
  const arm = () => {
    if (connected || timer) return;
    timer = setTimeout(() => { timer = null; if (!connected) onFail(UNREACHABLE); }, CONNECT_TIMEOUT_MS);
  };
  return { arm, stop };
}
