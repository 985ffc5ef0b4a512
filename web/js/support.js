// SPDX-License-Identifier: LGPL-2.1-or-later
// What the pages need of the browser, said in words before anything fails
// on its absence (a console's "RTCPeerConnection is not defined" tells a
// visitor nothing).

/// Why this browser cannot show the stream: null when it can. `room`: the
/// page draws the 3D room (WebGL 2, three.js's only renderer) too.
export function missingSupport({ room = true } = {}) {
  if (typeof RTCPeerConnection !== 'function')
    return 'this browser cannot receive the video stream (it has no WebRTC, or it is turned off)';
  if (room && !webGL2()) {
    return 'this browser cannot draw the 3D view (WebGL 2 is turned off or not supported here); ' +
      'turn on hardware acceleration or try another browser';
  }
  return null;
}

function webGL2() {
  const gl = document.createElement('canvas').getContext('webgl2');
  gl?.getExtension('WEBGL_lose_context')?.loseContext();  // a context held for nothing counts against the page's few
  return Boolean(gl);
}
