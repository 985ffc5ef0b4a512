// SPDX-License-Identifier: LGPL-2.1-or-later
// Ports a test picks and hands to another program (Janus, a server started
// again on the port it had). A port free when picked may be taken before
// the program binds it, by any process that binds port 0 or connects out:
// so the ports come from below the range the kernel hands those out from,
// and the test asks the kernel whether its program is what listens there.
import { readFileSync, readdirSync, readlinkSync } from 'node:fs';
import net from 'node:net';

const bindable = (port) => new Promise((resolve) => {
  const s = net.createServer().once('error', () => resolve(0))
    .listen(port, '127.0.0.1', () => { const { port: got } = s.address(); s.close(() => resolve(got)); });
});

/// A loopback TCP port free now, below the kernel's range for port 0 and
/// outgoing connections (/proc/sys/net/ipv4/ip_local_port_range) where that
/// range leaves 10,000 ports below it; the kernel's pick otherwise.
export async function quietPort() {
  const [low] = readFileSync('/proc/sys/net/ipv4/ip_local_port_range', 'utf8').trim().split(/\s+/).map(Number);
  if (low >= 11024) {
    for (let i = 0; i < 50; i += 1) {
      const port = await bindable(low - 10000 + Math.floor(Math.random() * 10000));
      if (port) return port;
    }
  }
  return bindable(0);
}

// The inodes of the TCP sockets listening on `port` (any address).
function listeners(port) {
  const inodes = [];
  for (const table of ['/proc/net/tcp', '/proc/net/tcp6']) {
    let lines = [];
    try { lines = readFileSync(table, 'utf8').trim().split('\n').slice(1); } catch { continue; }
    for (const line of lines) {
      // sl local_address rem_address st tx:rx tr:when retrnsmt uid timeout inode
      const f = line.trim().split(/\s+/);
      if (f[3] === '0A' && parseInt(f[1].split(':').pop(), 16) === port) inodes.push(f[9]);
    }
  }
  return inodes;
}

/// Whether process `pid` listens on TCP `port` and no other process does
/// (SO_REUSEPORT lets processes share a port).
export function holdsPort(pid, port) {
  const own = new Set();
  try {
    for (const fd of readdirSync(`/proc/${pid}/fd`)) {
      try {
        const m = /^socket:\[(\d+)\]$/.exec(readlinkSync(`/proc/${pid}/fd/${fd}`));
        if (m) own.add(m[1]);
      } catch { /* closed meanwhile */ }
    }
  } catch { return false; }  // exited
  const held = listeners(port);
  return held.length > 0 && held.every((inode) => own.has(inode));
}
