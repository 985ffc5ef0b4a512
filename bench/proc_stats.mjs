// SPDX-License-Identifier: LGPL-2.1-or-later
// A process's CPU time and memory from /proc, for the benchmarks that
// weigh causticd, Janus and their viewers against one another.
import { readFileSync } from 'node:fs';

/// utime + stime of process `pid`, in seconds.
export function cpuSeconds(pid) {
  const fields = readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / 100;  // USER_HZ is 100 on Linux
}

/// Resident memory of process `pid`, in MiB.
export function rssMiB(pid) {
  const line = readFileSync(`/proc/${pid}/status`, 'utf8').split('\n').find((l) => l.startsWith('VmRSS:'));
  return Number(line.split(/\s+/)[1]) / 1024;
}
