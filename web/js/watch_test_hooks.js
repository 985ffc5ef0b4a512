// SPDX-License-Identifier: LGPL-2.1-or-later
// What scripts (the browser tests) may read of a broadcast viewer's page,
// on window.caustic beside the state the page keeps. `parts` returns the
// page's current room, stream, water, receivers and paired frames (the
// stream changes when the page connects again); the stream itself, which
// holds the link's token and pin, is never handed out.
import { drawnHeights, surfaceTiles } from './test_probes.js';

export function installWatchTestHooks(state, parts) {
  // How long a late joiner waited for its first picture: when the page
  // first said live and when the video first showed a frame
  // (performance.now(), 0 until then).
  state.connectedAt = state.firstFrameAt = 0;
  const label = document.getElementById('state');
  new MutationObserver(() => {
    if (!state.connectedAt && label.dataset.state === 'live') state.connectedAt = performance.now();
  }).observe(label, { attributes: true, attributeFilter: ['data-state'] });
  const video = document.getElementById('video');
  if ('requestVideoFrameCallback' in video) video.requestVideoFrameCallback((now) => { state.firstFrameAt = now; });
  // How many receivers the room shows.
  state.receivers = () => parts().receivers.shown?.length ?? 0;
  // Frames whose data message met their picture.
  state.framesPaired = () => parts().frames.paired;
  // The water's heights as drawn (metres), or null without water.
  state.waterHeights = () => (parts().water ? drawnHeights(parts().water.surface) : null);
  // The surfaces' lightmaps (test_probes.js).
  state.surfaces = () => surfaceTiles(parts().room);
  // The stream's peer connection (its statistics).
  state.peer = () => parts().stream?.pc;
  // The room (null until the scene's description came).
  state.room = () => parts().room;
}
