// SPDX-License-Identifier: LGPL-2.1-or-later
// A broadcast to many viewers, for real: one broadcast session, N viewers
// joining Janus one after another (caustic-janus-viewers: a WebRTC peer
// each, ICE, DTLS and SRTP of its own, counting frames without decoding,
// the first one decoding), then the holder drags the light at 30 Hz and,
// after a few seconds, for `seconds` it measures every viewer's frame rate against the frames
// causticd sent, and the CPU of causticd, Janus and the viewers' process.
// Prints a table; asserts nothing. Runs in a network namespace of its own
// (Janus needs one for ICE; root):
//
//   CAUSTICD=build/bin/causticd CAUSTIC_NODE_MODULES=build/npm/node_modules CAUSTIC_JANUS_DIR=janus \
//     tests/janus/in_namespace.sh node bench/broadcast_many.mjs [viewers, 50] [seconds, 20] [size, 320] [codec, vp8]
import { spawn } from 'node:child_process';
import os from 'node:os';
import path from 'node:path';
import readline from 'node:readline';

import { api, Janus, sentFrames } from '../tests/browser/janus_harness.mjs';
import { cpuSeconds, rssMiB } from './proc_stats.mjs';

const viewers = Number(process.argv[2] ?? 50);
const seconds = Number(process.argv[3] ?? 20);
const size = Number(process.argv[4] ?? 320);
const codec = process.argv[5] ?? 'vp8';
const viewersBinary = path.join(path.dirname(process.env.CAUSTICD), 'caustic-janus-viewers');

const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];

const janus = await Janus.start();
const server = await janus.startServer([], { width: size, height: size });
let audience;
try {
  const session = (await api(server, 'POST', '/api/v1/sessions', { scene: 'wavy', mode: 'broadcast', codec })).body;
  const link = (await api(server, 'POST', session.viewers_url, null, session.token)).body;
  audience = spawn(viewersBinary, ['--janus', link.janus_url, '--mountpoint', `${link.mountpoint}`, '--pin', link.pin,
                                   '--token', link.token, '--viewers', `${viewers}`, '--timeout-s', `${seconds + 240}`],
                   { stdio: ['pipe', 'pipe', 'inherit'] });
  const lines = readline.createInterface({ input: audience.stdout });
  const next = () => new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error('the viewers did not answer in 180 s')), 180000);
    lines.once('line', (l) => { clearTimeout(timer); resolve(l); });
  });
  const joinStart = performance.now();
  const ready = await next();
  if (ready !== `ready ${viewers}`) throw new Error(`viewers: ${ready}`);
  console.log(`machine: ${os.cpus().length} cores, ${os.cpus()[0].model}; ${size}x${size} ${codec} broadcast; ` +
              `${viewers} viewers joined in ${((performance.now() - joinStart) / 1000).toFixed(1)} s; ` +
              `holder dragging at 30 Hz for ${seconds} s`);

  // The drag runs `warmup` seconds before the window: the first viewer's
  // decoder waits for a key frame, which the moving picture brings.
  const warmup = 5;
  let sent0, cpu0, start;
  const pids = [server.pid, janus.process.pid, audience.pid];
  const dragStart = performance.now();
  // A PATCH every 33.3 ms, each on its own (at most two in flight): a
  // hand's drag does not wait for the answers.
  const inFlight = new Set();
  let patches = 0, patches0 = 0;
  for (let i = 0; !start || performance.now() - start < seconds * 1000; i += 1) {
    if (!start && performance.now() - dragStart >= warmup * 1000) {
      audience.stdin.write('mark\n');
      sent0 = await sentFrames(server);
      cpu0 = pids.map(cpuSeconds);
      patches0 = patches;
      start = performance.now();
    }
    if (inFlight.size >= 2) await Promise.race(inFlight);
    const patch = api(server, 'PATCH', `${session.url}/params`,
                      { light: { direction: [0.25 * Math.sin(i / 15), 0.1, -1] } }, session.token)
      .then(() => { patches += 1; inFlight.delete(patch); });
    inFlight.add(patch);
    const due = dragStart + (i + 1) * 33.3;
    await new Promise((resolve) => setTimeout(resolve, Math.max(0, due - performance.now())));
  }
  await Promise.all(inFlight);
  const wall = (performance.now() - start) / 1000;
  const cpu = pids.map((pid, i) => (100 * (cpuSeconds(pid) - cpu0[i])) / wall);
  const sent = ((await sentFrames(server)) - sent0) / wall;
  const janusRss = rssMiB(janus.process.pid), audienceRss = rssMiB(audience.pid);
  const reported = next();
  audience.stdin.write('report\n');
  const report = JSON.parse(await reported);
  const fps = report.frames.map((f) => f / report.window_s);
  const joins = report.join_ms.filter((ms) => ms >= 0);
  console.log(`PATCHes answered: ${((patches - patches0) / wall).toFixed(1)}/s; frames sent by causticd: ${sent.toFixed(1)}/s`);
  console.log(`viewers' frame rate: slowest ${Math.min(...fps).toFixed(1)}, median ${median(fps).toFixed(1)}, ` +
              `fastest ${Math.max(...fps).toFixed(1)} fps; ${fps.filter((f) => f >= 0.97 * sent).length} of ` +
              `${fps.length} within 3% of the frames sent`);
  console.log(`first viewer decoded ${(report.decoded_first / report.window_s).toFixed(1)} fps`);
  console.log(`join (connection -> first frame, while the others join): median ${median(joins).toFixed(0)} ms, ` +
              `max ${Math.max(...joins).toFixed(0)} ms`);
  console.log(`CPU (% of one core): causticd ${cpu[0].toFixed(1)}, Janus ${cpu[1].toFixed(1)} ` +
              `(${(cpu[1] / viewers).toFixed(2)} a viewer, its own base included), the viewers' process ${cpu[2].toFixed(1)}`);
  console.log(`memory: Janus ${janusRss.toFixed(0)} MiB, the viewers' process ${audienceRss.toFixed(0)} MiB`);
  if (report.errors.length) console.log(`viewer errors: ${report.errors.slice(0, 3).join('; ')}`);
} finally {
  audience?.kill('SIGTERM');
  // causticd destroys its mountpoint on the way out: Janus must still answer.
  await new Promise((resolve) => { server.once('exit', resolve); server.kill('SIGTERM'); });
  await janus.stop();
}
