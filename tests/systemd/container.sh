# SPDX-License-Identifier: LGPL-2.1-or-later
# Helpers for the real-systemd test (sourced): a minimal Debian 12 root made
# once with debootstrap and kept outside the checkout, a throw-away overlay
# on top of it for each run, and a booted systemd-nspawn container on that
# overlay. Every wait is bounded.

cache="${CAUSTICD_TEST_ROOT_CACHE:-/var/cache/causticd-test}"
base="$cache/bookworm-minbase"

skip() {
  echo "SKIP: $*"
  exit 77
}
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
note() { echo "== $*"; }

# The cached root: Debian 12 minbase with systemd, dbus and apt, and the
# host's apt sources (so that versions built against here resolve there).
prepare_base() {
  mkdir -p "$cache"
  exec 9>"$cache/.lock"
  flock -w 900 9 || fail "another run holds $cache/.lock"
  if [[ ! -f "$base/.complete" ]]; then
    note "preparing $base (once; about 1-3 minutes)"
    rm -rf "$base.tmp"
    debootstrap --variant=minbase --include=systemd,systemd-sysv,dbus bookworm "$base.tmp" >"$cache/debootstrap.log" 2>&1 ||
      fail "debootstrap failed: $(tail -3 "$cache/debootstrap.log")"
    rm -rf "$base"
    mv "$base.tmp" "$base"
    touch "$base/.complete"
  fi
  flock -u 9
}

# A fresh overlay of the cached root in $work/root; nothing of a run reaches
# the cache except downloaded packages ($cache/archives).
make_overlay() {
  work="$(mktemp -d /var/tmp/causticd-systemd-test.XXXXXX)"
  mkdir -p "$work/upper" "$work/ovl" "$work/root" "$cache/archives/partial"
  mount -t overlay overlay -o "lowerdir=$base,upperdir=$work/upper,workdir=$work/ovl" "$work/root" ||
    skip "cannot mount an overlay file system here"
  rm -f "$work/root/etc/apt/sources.list"
  cp /etc/apt/sources.list.d/*.sources "$work/root/etc/apt/sources.list.d/" 2>/dev/null || true
  if [[ -f /etc/apt/sources.list ]]; then cp /etc/apt/sources.list "$work/root/etc/apt/sources.list"; fi
}

# Runs a command in the (not booted) root with the host's network: apt.
in_root() {
  SYSTEMD_NSPAWN_UNIFIED_HIERARCHY=1 systemd-nspawn -q -D "$work/root" --register=no --keep-unit --pipe \
    --bind="$cache/archives:/var/cache/apt/archives" "$@"
}

nspawn_pid=""
init_pid=""
# Boots the root with systemd as PID 1, on a network of its own.
boot() {
  SYSTEMD_NSPAWN_UNIFIED_HIERARCHY=1 systemd-nspawn -q -D "$work/root" -b --register=no --keep-unit \
    --private-network --console=pipe --system-call-filter=bpf >>"$work/console.log" 2>&1 </dev/null &
  nspawn_pid=$!
  init_pid=""
  for _ in $(seq 1 300); do
    init_pid="$(pgrep -P "$nspawn_pid" -x systemd 2>/dev/null | head -1 || true)"
    [[ -n "$init_pid" ]] && break
    kill -0 "$nspawn_pid" 2>/dev/null || fail "the container did not boot: $(tail -5 "$work/console.log")"
    sleep 0.1
  done
  [[ -n "$init_pid" ]] || fail "no systemd in the container after 30 s"
  local state=""
  for _ in $(seq 1 600); do
    state="$(c systemctl is-system-running 2>/dev/null || true)"
    [[ "$state" == running || "$state" == degraded ]] && return 0
    sleep 0.1
  done
  local said
  said="$(tail -8 "$work/console.log")"
  fail "the container's systemd is \"$state\" after 60 s; its console said: ${said:-nothing}"
}

# A command inside the booted container (all its namespaces).
c() { nsenter -t "$init_pid" -a "$@"; }
# A command of the host run in the container's network (curl from here).
on_net() { nsenter -t "$init_pid" -n "$@"; }

# Waits until the container's PID 1 has exited (after poweroff or reboot).
wait_down() {
  for _ in $(seq 1 600); do
    kill -0 "$nspawn_pid" 2>/dev/null || {
      wait "$nspawn_pid" || true
      return 0
    }
    sleep 0.1
  done
  fail "the container did not go down within 60 s"
}

cleanup() {
  if [[ -n "$nspawn_pid" ]] && kill -0 "$nspawn_pid" 2>/dev/null; then
    kill -TERM "$nspawn_pid" 2>/dev/null || true
    for _ in $(seq 1 100); do kill -0 "$nspawn_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$nspawn_pid" 2>/dev/null || true
  fi
  if [[ -n "${work:-}" ]]; then
    umount "$work/root" 2>/dev/null || umount -l "$work/root" 2>/dev/null || true
    rm -rf "$work"
  fi
}
