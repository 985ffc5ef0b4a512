// SPDX-License-Identifier: LGPL-2.1-or-later
// What the broadcast test and benchmark share: Janus from the shipped
// configuration (janus/, with ports and secrets of their own), a causticd
// that broadcasts through it, the REST calls of a session's holder, and the
// video counters of a viewer page. Runs inside tests/janus/in_namespace.sh
// (JANUS_ICE_INTERFACE).
import { spawn } from 'node:child_process';
import { mkdtempSync, openSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';

import { startServer } from './harness.mjs';

const secrets = { admin: 'bc-admin-secret-0123456', key: 'bc-streaming-key-012345', token: 'bc-token-secret-0123456' };

const freePort = () => new Promise((resolve) => {
  const s = net.createServer().listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
});

export class Janus {
  static async start() {
    const janus = new Janus();
    janus.dir = mkdtempSync('/tmp/causticd-janus-');
    janus.ports = { admin: await freePort(), ws: await freePort() };
    for (const name of readdirSync(process.env.CAUSTIC_JANUS_DIR).filter((n) => n.endsWith('.jcfg'))) {
      const text = readFileSync(path.join(process.env.CAUSTIC_JANUS_DIR, name), 'utf8')
        .replaceAll('@JANUS_ADMIN_SECRET@', secrets.admin)
        .replaceAll('@JANUS_TOKEN_SECRET@', secrets.token).replaceAll('@JANUS_STREAMING_KEY@', secrets.key)
        .replace('admin_port = 7088', `admin_port = ${janus.ports.admin}`)
        .replace('ws_port = 8188', `ws_port = ${janus.ports.ws}`);
      writeFileSync(path.join(janus.dir, name), text);
    }
    await janus.run();
    return janus;
  }

  async run() {
    const log = openSync(`${this.dir}/janus.log`, 'a');
    this.process = spawn('janus', ['-F', this.dir, '-C', `${this.dir}/janus.jcfg`, '-o', '-d', '3',
                                    '-E', process.env.JANUS_ICE_INTERFACE], { stdio: ['ignore', log, log] });
    for (let i = 0; i < 100; i += 1) {
      const up = await new Promise((resolve) => {
        const c = net.connect(this.ports.ws, '127.0.0.1', () => { c.destroy(); resolve(true); })
          .on('error', () => resolve(false));
      });
      if (up) return;
      await new Promise((r) => setTimeout(r, 100));
    }
    throw new Error('janus did not start');
  }

  stop() { return new Promise((resolve) => { this.process.once('exit', resolve); this.process.kill('SIGTERM'); }); }

  /// A causticd that broadcasts through this Janus.
  startServer(extra = [], size = undefined) {
    return startServer(['--set', `janus_admin_url=http://127.0.0.1:${this.ports.admin}/admin`,
                        '--set', `janus_admin_secret=${secrets.admin}`, '--set', `janus_streaming_key=${secrets.key}`,
                        '--set', `janus_token_secret=${secrets.token}`,
                        '--set', `janus_ws_url=ws://127.0.0.1:${this.ports.ws}/`, '--set', 'drain_timeout_s=0', ...extra],
                       size);
  }
}

/// A REST call to `server` with the holder's `token`.
export async function api(server, method, url, body, token) {
  const response = await fetch(`${server.url}${url}`, {
    method, headers: { 'Content-Type': 'application/json', ...(token ? { Authorization: `Bearer ${token}` } : {}) },
    body: body ? JSON.stringify(body) : undefined,
  });
  return { status: response.status, body: response.status === 204 ? null : await response.json() };
}

/// Frames the server has encoded and sent, in all.
export async function sentFrames(server) {
  const text = await (await fetch(`${server.url}/metrics`)).text();
  return Number(/causticd_frames_sent_total (\d+)/.exec(text)[1]);
}

/// In a viewer page: an inbound video counter (framesReceived, framesDecoded...).
export const videoStat = (name) => window.caustic.peer()?.getStats().then((report) => {
  let n = 0;
  report.forEach((r) => { if (r.type === 'inbound-rtp' && r.kind === 'video') n = r[name]; });
  return n;
});
