#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Runs a command (the broadcast browser test, the broadcast benchmark) in a
# private network namespace: Janus never gathers ICE candidates on a
# loopback interface, so the namespace gets a veth carrying 127.0.0.2 for
# Janus's ICE (JANUS_ICE_INTERFACE), and everything (Janus, causticd,
# chromium) talks inside it, to nothing outside. Exits 77 (skipped) only
# where namespaces cannot be made or entered (not root, no ip netns).
#   in_namespace.sh COMMAND [ARG...]
set -euo pipefail
(($#)) || { echo "usage: in_namespace.sh COMMAND [ARG...]" >&2; exit 2; }
skip() { echo "SKIPPED: $*"; exit 77; }
[[ $(id -u) -eq 0 ]] || skip "network namespaces need root"
command -v ip >/dev/null || skip "no ip (iproute2)"
command -v janus >/dev/null || skip "janus is not installed (tools/bootstrap.sh installs it)"
ns="causticd-bc-$$"
ip netns add "$ns" 2>/dev/null || skip "cannot create a network namespace here"
trap 'ip netns del "$ns" 2>/dev/null || true' EXIT
# Entering it remounts / as a slave, which a chroot whose / is no mount
# point refuses ("mount --make-rslave /": Invalid argument).
why="$(ip netns exec "$ns" true 2>&1)" || skip "cannot enter a network namespace here: $why"
ip -n "$ns" link set lo up
# "type dummy" needs a kernel module that some hosts lack; a veth pair does not.
ip -n "$ns" link add jv0 type veth peer name jv1
ip -n "$ns" addr add 127.0.0.2/32 dev jv0
ip -n "$ns" link set jv0 up
ip -n "$ns" link set jv1 up
# Bounded: the command's own waits are, and this caps them all.
timeout "${CAUSTIC_NAMESPACE_TIMEOUT:-540}" ip netns exec "$ns" env JANUS_ICE_INTERFACE=jv0 "$@"
