#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Sets up a Debian 12 machine for causticd, builds it, then runs it or tests it.
#   bash tools/bootstrap.sh run    # install what is missing, build, run the main job
#   bash tools/bootstrap.sh test   # install what is missing, build, run every test
# Needs root (or sudo) only when packages are missing.
set -euo pipefail

# A bare chroot (debootstrap) has no /proc: causticd finds its data through
# /proc/self/exe, and the tests read /proc. Mounted when root can, else said.
if [[ ! -e /proc/self/exe ]]; then
  if [[ $(id -u) -eq 0 ]] && mount -t proc proc /proc 2>/dev/null; then
    echo "== mounted /proc (it was not mounted)"
  else
    echo "bootstrap: /proc is not mounted; mount it (mount -t proc proc /proc) and run again" >&2
    exit 2
  fi
fi

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CAUSTICD_BUILD_DIR:-$here/build}"
mode="${1:-}"
case "$mode" in
  run | test | build) ;;
  *)
    echo "usage: bash tools/bootstrap.sh run|test|build" >&2
    exit 2
    ;;
esac

# Every Debian package the build, the tests and the headless renderer need
# (the last lines: the plugin test's gst-inspect-1.0 and gst-launch-1.0, the
# Debian package and lintian, the real-systemd test's container, the
# proxies the scaling tests put in front of two instances, and Janus with
# the network namespace its broadcast test needs).
packages=(
  g++ make cmake pkg-config
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  libglm-dev nlohmann-json3-dev libtinyobjloader-dev libcli11-dev
  libopenimageio-dev zlib1g-dev libembree-dev libfftw3-dev gnuplot-nox
  libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev libgstreamer-plugins-bad1.0-dev
  gstreamer1.0-plugins-base gstreamer1.0-plugins-good gstreamer1.0-plugins-bad gstreamer1.0-plugins-ugly
  gstreamer1.0-nice gstreamer1.0-libav libsoup-3.0-dev
  libsystemd-dev systemd
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  chromium
  fonts-dejavu-core
  gstreamer1.0-tools
  dpkg-dev file lintian
  systemd-container debootstrap curl
  haproxy nginx janus iproute2
)
# Node.js and npm vendor three.js and run the browser tests. A machine that
# already has them (for example from another repository) keeps its own.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  sudo=()
  if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
  "${sudo[@]}" apt-get update -q
  # The tests run the proxies and Janus as their own processes: their Debian
  # services (nginx's default site on port 80, Janus's sample configuration
  # with its well-known admin secret) are not started by this install.
  # Where no policy is in place, one that denies service starts is, for the
  # install alone.
  policy=/usr/sbin/policy-rc.d made_policy=0
  if [[ ! -e $policy ]]; then
    made_policy=1
    printf '#!/bin/sh\nexit 101\n' | "${sudo[@]}" tee "$policy" >/dev/null
    "${sudo[@]}" chmod 755 "$policy"
    trap '"${sudo[@]}" rm -f "$policy"' EXIT
  fi
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
  if ((made_policy)); then
    "${sudo[@]}" rm -f "$policy"
    trap - EXIT
  fi
  # Nor started at the next boot, those this install brought: Debian's
  # janus.service would serve its sample configuration, nginx and HAProxy
  # would take port 80 (docs/scaling.md runs the appliance's own).
  for service in janus nginx haproxy; do
    if [[ " ${missing[*]} " == *" $service "* ]] && command -v systemctl >/dev/null; then
      "${sudo[@]}" systemctl disable --quiet "$service.service" 2>/dev/null || true
    fi
  done
fi

# The photographs of the built-in designed scenes are scikit-image's test
# pictures (assets/README.md). Only the package file is fetched and unpacked
# into the build folder: installing python3-skimage would pull in SciPy and
# more that nothing here uses. Without it the photographic designs are
# skipped and the build goes on.
photo_args=()
deps="$build/deps"
photo_dir="$deps/skimage/usr/lib/python3/dist-packages/skimage/data"
if [[ ! -f "$photo_dir/chelsea.png" ]]; then
  echo "== fetching python3-skimage (pictures for the designed scenes) into $deps"
  mkdir -p "$deps"
  # Fetched in a folder of its own that apt's unprivileged downloader (the
  # _apt user, when root runs this) may write, then unpacked here.
  fetch="$(mktemp -d)"
  if [[ $(id -u) -eq 0 ]] && id _apt >/dev/null 2>&1; then chown _apt "$fetch"; fi
  # Package lists cleaned away (a container image) are fetched once more.
  download() { (cd "$fetch" && apt-get download -q python3-skimage); }
  if ! download && [[ $(id -u) -eq 0 ]]; then
    apt-get update -q >/dev/null 2>&1 || true
    download || true
  fi
  if ls "$fetch"/python3-skimage_*.deb >/dev/null 2>&1 && dpkg-deb -x "$fetch"/python3-skimage_*.deb "$deps/skimage"; then
    rm -rf "$fetch"
  else
    rm -rf "$fetch"
    echo "== python3-skimage could not be fetched: the photographic designs will be skipped" >&2
  fi
fi
if [[ -f "$photo_dir/chelsea.png" ]]; then photo_args=(-DCAUSTICD_DESIGN_PHOTO_DIR="$photo_dir"); fi

jobs="$(nproc 2>/dev/null || echo 2)"
echo "== configuring and building in $build"
# Line tables only (-g1): a backtrace still names file and line, and the
# build (nearly half of the test command on two cores) takes about a fifth
# less than with full debug information. Configure with cmake directly
# (RelWithDebInfo is the default) for variables in a debugger.
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  "${photo_args[@]}"
cmake --build "$build" -j "$jobs"

case "$mode" in
  run)
    echo "== serving the built-in scenes on http://localhost:8080 (Ctrl-C stops)"
    exec "$build/bin/causticd" serve --bind 127.0.0.1 --port 8080
    ;;
  test)
    cd "$build"
    ctest --output-on-failure -j "$jobs"
    ;;
esac
