// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's stats overlay: what the browser measures of the stream (its
// WebRTC statistics), how far behind the parameters the picture is, and
// what the server renders with what expected error, once a second while
// the overlay is shown.

/// What the server renders and how far from the reference it is expected to be.
export function fidelityText(f) {
  if (!f) return '';
  // The mesh as loaded keeps its vertex count to itself (the server does not tell it).
  const mesh = f.mesh_resolution ? `${f.mesh_resolution}\u00b2 mesh (${f.vertices} vertices)` : 'mesh as loaded';
  let text = `fidelity ${f.mode}: ${mesh}, ${f.point_model} point model, Fresnel ${f.fresnel ? 'on' : 'off'}`;
  if (f.expected_relative_l1 === null) return `${text}; not calibrated`;
  text += `; expected L1 ${(100 * f.expected_relative_l1).toFixed(2)}% (target ${(100 * f.accuracy_target).toFixed(1)}%)`;
  if (!f.calibration_matches_parameters) text += ', calibrated before the scene was changed';
  return text;
}

/// Fills `panel` once a second while it is shown, from the peer connection
/// `peer()` returns (none: nothing to show yet) and the page's `state`
/// (latencies, versions, level, fidelity).
export function showStats(panel, peer, state) {
  let lastBytes = 0, lastTime = 0;  // for the bitrate between two reports
  setInterval(async () => {
    const pc = peer();
    if (panel.hidden || !pc) return;
    const report = await pc.getStats();
    let text = '';
    report.forEach((r) => {
      if (r.type === 'inbound-rtp' && r.kind === 'video') {
        const kbps = lastTime ? (8 * (r.bytesReceived - lastBytes)) / (r.timestamp - lastTime) : 0;
        lastBytes = r.bytesReceived;
        lastTime = r.timestamp;
        text += `fps ${r.framesPerSecond ?? 0}  bitrate ${kbps.toFixed(0)} kbit/s  jitter ${(1000 * r.jitter).toFixed(1)} ms  dropped ${r.framesDropped ?? 0}\n`;
      }
      if (r.type === 'candidate-pair' && r.nominated && r.currentRoundTripTime !== undefined)
        text += `round trip ${(1000 * r.currentRoundTripTime).toFixed(1)} ms\n`;
    });
    const l = [...state.latencies].sort((a, b) => a - b);
    if (l.length) text += `PATCH to frame: median ${l[l.length >> 1].toFixed(0)} ms over ${l.length}\n`;
    text += `parameter version ${state.version}, on screen ${state.shownVersion}`;
    text += state.shownLevel === 1 ? ' (preview while moving)\n' : ' (full quality)\n';
    text += fidelityText(state.fidelity);
    panel.textContent = text;
  }, 1000);
}
