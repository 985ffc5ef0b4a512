// SPDX-License-Identifier: LGPL-2.1-or-later
// The viewer's frame rate in headless Debian chromium (software WebGL), as
// requestAnimationFrame counts it, still and while the light is dragged
// (a scripted light move every 100 ms, the path a drag takes), for each
// room quality; beside it, over the same window, the stream's frames the
// browser decoded (WebRTC stats) and the video frames it presented
// (requestVideoFrameCallback): what reaches the page, apart from what the
// page's own drawing keeps up with. Prints one line per case with the machine.
//
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules \
//     node bench/page_fps.mjs [scene] [seconds] [stream size] [causticd serve options...]
//
// For example `slab 10 1024 --set still_interval_ms=0`: a still scene sent
// at 30 fps, which the server encodes but does not render, leaves the
// cores to the page: what the page draws when the server is elsewhere.
import os from 'node:os';

import { launchChromium } from '../tests/browser/chromium.mjs';
import { startServer, until } from '../tests/browser/harness.mjs';

const scene = process.argv[2] ?? 'wavy';
const seconds = Number(process.argv[3] ?? 5);
const streamSize = Number(process.argv[4] ?? 1024);
const serverOptions = process.argv.slice(5);

// Frames a second in `ms` (while the light moves, with `drag`): the page's
// own requestAnimationFrame, the video frames presented, and the frames
// decoded.
const countFrames = ([ms, drag]) => new Promise((resolve) => {
  const decoded = () => window.caustic.peer.getStats().then((report) => {
    let n = 0;
    report.forEach((r) => { if (r.type === 'inbound-rtp' && r.kind === 'video') n = r.framesDecoded; });
    return n;
  });
  const video = document.getElementById('video');
  decoded().then((decodedBefore) => {
    const timer = drag ? setInterval(() => window.caustic.moveLight(0.3, 0, 0), 100) : null;
    let frames = 0, presented = 0, done = false;
    const start = performance.now();
    const onVideo = () => {
      ++presented;
      if (!done) video.requestVideoFrameCallback(onVideo);
    };
    video.requestVideoFrameCallback(onVideo);
    const tick = (now) => {
      if (now - start < ms) {
        ++frames;
        return requestAnimationFrame(tick);
      }
      done = true;
      clearInterval(timer);
      const per = (n) => (1000 * n) / (now - start);
      decoded().then((decodedAfter) =>
        resolve({ page: per(frames), presented: per(presented), decoded: per(decodedAfter - decodedBefore) }));
    };
    requestAnimationFrame(tick);
  });
});

const server = await startServer(serverOptions, { width: streamSize, height: streamSize });
const browser = await launchChromium();
try {
  console.log(`machine: ${os.cpus()[0].model}, ${os.cpus().length} cores; chromium software WebGL; stream ${streamSize}x${streamSize} VP8; page 1280x800; server ${serverOptions.join(' ') || 'defaults'}`);
  for (const quality of ['high', 'low']) {
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    await page.goto(`${server.url}/viewer.html?scene=${scene}&codec=vp8&quality=${quality}`);
    await until(page, () => window.caustic.connection === 'live' && window.caustic.shownVersion >= 1, 60, 'live');
    await page.waitForTimeout(1500);
    const still = await page.evaluate(countFrames, [seconds * 1000, false]);
    const drag = await page.evaluate(countFrames, [seconds * 1000, true]);
    const rates = (r) => `page ${r.page.toFixed(1)} fps, video presented ${r.presented.toFixed(1)}, decoded ${r.decoded.toFixed(1)}`;
    console.log(`${scene} room ${quality}: still ${rates(still)}; during a light drag ${rates(drag)}`);
    await page.close();
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
