// SPDX-License-Identifier: LGPL-2.1-or-later
// What the browser tests share: a real `causticd serve` on 127.0.0.1 (ICE
// pinned to loopback, a small stream, designs in a folder of the test's
// own) and bounded polling of the page.
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import readline from 'node:readline';

export const shots = process.env.CAUSTIC_SCREENSHOTS ?? '/tmp';

export async function startServer(extra = [], { width = 320, height = 240 } = {}) {
  const port = extra.includes('--port') ? [] : ['--port', '0'];
  const server = spawn(process.env.CAUSTICD, ['serve', ...port, '--ice-address', '127.0.0.1', '--width', `${width}`,
                                              '--height', `${height}`, ...extra], {
    stdio: ['ignore', 'pipe', 'inherit'],
    // Designs go to a folder of the test's own, never the user's state.
    env: { ...process.env, XDG_STATE_HOME: mkdtempSync('/tmp/causticd-state-') },
  });
  const line = await new Promise((resolve, reject) => {
    // Loading the gallery renders every thumbnail: 17 to 61 s measured on a
    // 2-core machine beside stress-ng --cpu 4 and other tests (seconds when
    // idle), so the bound is three minutes; a server that exits instead
    // fails at once, not at the bound.
    const timer = setTimeout(() => reject(new Error('server did not start within 180 s')), 180000);
    const exited = (code, signal) => {
      clearTimeout(timer);
      reject(new Error(`server exited before it listened (${signal ?? `status ${code}`})`));
    };
    server.once('exit', exited);
    server.once('error', (e) => { clearTimeout(timer); reject(e); });
    readline.createInterface({ input: server.stdout }).once('line', (l) => {
      clearTimeout(timer);
      server.off('exit', exited);
      resolve(l);
    });
  });
  server.url = line.replace('listening on ', '').replace(/\/$/, '');
  return server;
}

/// Runs `fn(server)` against a fresh startServer(...args) (the arguments
/// before `fn`) and stops the server however `fn` ends, so that a failed
/// assertion never leaves a server behind for the next test.
export async function withServer(...args) {
  const fn = args.pop();
  const server = await startServer(...args);
  try {
    return await fn(server);
  } finally {
    await stopServer(server);
  }
}

/// Stops a server as an operator in a hurry does and resolves once it has
/// exited: SIGTERM, then, when running sessions keep it draining (up to a
/// minute), a second SIGTERM, which stops it at once; SIGKILL after 10 s
/// more. A server left draining would render beside the next test.
export async function stopServer(server) {
  if (server.exitCode !== null || server.signalCode !== null) return;
  const exited = new Promise((resolve) => server.once('exit', resolve));
  const within = async (ms) => {
    let timer;
    const late = new Promise((resolve) => { timer = setTimeout(() => resolve(false), ms); });
    const done = await Promise.race([exited.then(() => true), late]);
    clearTimeout(timer);
    return done;
  };
  server.kill('SIGTERM');
  if (await within(1000)) return;
  server.kill('SIGTERM');
  if (await within(10000)) return;
  server.kill('SIGKILL');
  await exited;
}

/// Polls `fn` in the page until it returns a truthy value or `seconds` pass.
export async function until(page, fn, seconds, what, arg) {
  for (let waited = 0; waited < seconds * 1000; waited += 250) {
    const value = await page.evaluate(fn, arg);
    if (value) return value;
    await page.waitForTimeout(250);
  }
  throw new Error(`timed out after ${seconds} s waiting for ${what}`);
}
