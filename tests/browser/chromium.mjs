// SPDX-License-Identifier: LGPL-2.1-or-later
// Debian's chromium as the tests and benchmarks drive it: headless, no
// sandbox (containers), software GL, WebRTC allowed over loopback without
// mDNS-hidden addresses, nothing fetched from the network.
import { createRequire } from 'node:module';
import path from 'node:path';

const ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
              '--disable-component-update', '--disable-sync', '--allow-loopback-in-peer-connection',
              '--disable-features=WebRtcHideLocalIpsWithMdns', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];

/// playwright-core from CAUSTIC_NODE_MODULES, launching /usr/bin/chromium.
export function launchChromium() {
  const { chromium } = createRequire(`${path.resolve(process.env.CAUSTIC_NODE_MODULES)}/`)('playwright-core');
  return chromium.launch({ executablePath: '/usr/bin/chromium', args: ARGS });
}
