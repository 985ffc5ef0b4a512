// SPDX-License-Identifier: LGPL-2.1-or-later
// What the broadcast test and benchmark share: Janus from the shipped
// configuration (janus/, with ports and secrets of their own), a causticd
// that broadcasts through it, the REST calls of a session's holder, and the
// video counters of a viewer page. Runs inside tests/janus/in_namespace.sh
// (JANUS_ICE_INTERFACE).
import { spawn } from 'node:child_process';
import { closeSync, mkdtempSync, openSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';

import { startServer } from './harness.mjs';
import { holdsPort, quietPort } from './ports.mjs';

const secrets = { admin: 'bc-admin-secret-0123456', key: 'bc-streaming-key-012345', token: 'bc-token-secret-0123456' };

export class Janus {
  // Up to three tries, each with new ports: one taken before Janus bound it
  // would leave something else answering there (see ports.mjs).
  static async start() {
    const janus = new Janus();
    janus.dir = mkdtempSync('/tmp/causticd-janus-');
    for (let attempt = 0; attempt < 3; attempt += 1) {
      janus.ports = { admin: await quietPort(), ws: await quietPort() };
      if (janus.ports.admin === janus.ports.ws) continue;
      for (const name of readdirSync(process.env.CAUSTIC_JANUS_DIR).filter((n) => n.endsWith('.jcfg'))) {
        const text = readFileSync(path.join(process.env.CAUSTIC_JANUS_DIR, name), 'utf8')
          .replaceAll('@JANUS_ADMIN_SECRET@', secrets.admin)
          .replaceAll('@JANUS_TOKEN_SECRET@', secrets.token).replaceAll('@JANUS_STREAMING_KEY@', secrets.key)
          .replace('admin_port = 7088', `admin_port = ${janus.ports.admin}`)
          .replace('ws_port = 8188', `ws_port = ${janus.ports.ws}`);
        writeFileSync(path.join(janus.dir, name), text);
      }
      if (await janus.tryRun()) return janus;
    }
    throw new Error(`janus did not hold the ports picked for it (three tries; ${janus.dir}/janus.log)`);
  }

  /// Starts Janus on its ports (again, after stop()): a Janus that does not
  /// hold them within 10 s is stopped and this throws.
  async run() {
    if (!(await this.tryRun())) throw new Error(`janus did not start on its ports (${this.dir}/janus.log)`);
  }

  // Whether Janus came to hold both its ports (its admin API answering with
  // this harness's secret); a Janus that did not is stopped, not left to
  // hold node's test run open.
  async tryRun() {
    const log = openSync(`${this.dir}/janus.log`, 'a');
    this.process = spawn('janus', ['-F', this.dir, '-C', `${this.dir}/janus.jcfg`, '-o', '-d', '3',
                                    '-E', process.env.JANUS_ICE_INTERFACE], { stdio: ['ignore', log, log] });
    closeSync(log);
    const end = Date.now() + 10000;
    while (Date.now() < end && this.process.exitCode === null && this.process.signalCode === null) {
      if (holdsPort(this.process.pid, this.ports.ws) && holdsPort(this.process.pid, this.ports.admin) &&
          await this.answersAdmin()) return true;
      await new Promise((r) => setTimeout(r, 100));
    }
    await this.stop();
    return false;
  }

  async answersAdmin() {
    try {
      const response = await fetch(`http://127.0.0.1:${this.ports.admin}/admin`, {
        method: 'POST', body: JSON.stringify({ janus: 'list_sessions', transaction: 't', admin_secret: secrets.admin }),
        signal: AbortSignal.timeout(2000),
      });
      return (await response.json()).janus === 'success';
    } catch {
      return false;
    }
  }

  /// SIGTERM; SIGKILL after 10 s (a Janus that hangs in its shutdown would
  /// hold the test run open until its timeout).
  stop() {
    const child = this.process;
    if (child.exitCode !== null || child.signalCode !== null) return Promise.resolve();
    return new Promise((resolve) => {
      const kill = setTimeout(() => child.kill('SIGKILL'), 10000);
      child.once('exit', () => { clearTimeout(kill); resolve(); });
      child.kill('SIGTERM');
    });
  }

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
