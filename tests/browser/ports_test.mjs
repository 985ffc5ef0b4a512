// SPDX-License-Identifier: LGPL-2.1-or-later
// The ports the browser tests hand to other programs: picked below the
// kernel's range for port 0, and held only when the program alone listens.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import net from 'node:net';
import { test } from 'node:test';

import { holdsPort, quietPort } from './ports.mjs';

const listen = (port = 0) => new Promise((resolve, reject) => {
  const s = net.createServer().once('error', reject).listen(port, '127.0.0.1', () => resolve(s));
});

// Another process listening on a port of its own; resolves with it and its port.
function otherListener() {
  const child = spawn(process.execPath, ['-e', `require('net').createServer().listen(0, '127.0.0.1', function () {
    console.log(this.address().port); setTimeout(() => process.exit(0), 60000); });`], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve) => child.stdout.once('data', (d) => resolve({ child, port: Number(String(d).trim()) })));
}

test('a quiet port is free and below the range the kernel hands out for port 0', async () => {
  const [low] = readFileSync('/proc/sys/net/ipv4/ip_local_port_range', 'utf8').trim().split(/\s+/).map(Number);
  const port = await quietPort();
  if (low >= 11024) assert.ok(port >= low - 10000 && port < low, `${port} against a range from ${low}`);
  (await listen(port)).close();
});

test('a port is held by the process that alone listens on it', async () => {
  const mine = await listen();
  const own = mine.address().port;
  const { child, port } = await otherListener();
  try {
    assert.ok(holdsPort(process.pid, own));
    assert.ok(holdsPort(child.pid, port));
    assert.ok(!holdsPort(process.pid, port), 'another process\'s port');
    assert.ok(!holdsPort(child.pid, own));
  } finally {
    child.kill();
    await new Promise((r) => mine.close(r));
  }
  assert.ok(!holdsPort(process.pid, own), 'nothing listens there now');
});
