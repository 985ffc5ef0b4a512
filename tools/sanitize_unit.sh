#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The unit suites under AddressSanitizer + UndefinedBehaviorSanitizer
# (tools/sanitize.sh unit [TEST...], docs/reliability-sanitizers.md):
# builds the gtest binaries of tests/ that need no running server in
# build-asan-tests/, runs each one, then replays every seed and regression
# of tests/fuzz through the libFuzzer targets (clang, build-asan-tests/fuzz).
# float-cast-overflow (a double out of an int's range converted to it) is
# not part of -fsanitize=undefined and is added by name;
# -fno-sanitize-recover=undefined makes a UBSan report fail its binary;
# _GLIBCXX_ASSERTIONS adds what ASan misses inside a vector's capacity and
# the standard library's preconditions (std::clamp's lo <= hi).
# Each binary's output goes to build-asan-tests/logs/<test>.log. Exits 1
# when a binary fails (a sanitizer report, a failed test, its timeout) or a
# fuzz input is refused by its target's sanitizers or checks.
# Leaks are checked where no GL or GStreamer runs: Mesa's llvmpipe leaks by
# design, and GLib's quark table (tools/sanitize.sh asan) has no stack to
# tell it apart.
# The data the suites read: meshes, scenes and designs are made here
# (caustic-assetgen and causticd design run sanitized too); the fidelity
# calibrations and web/ are copied from the normal build (build/) when it has
# them, since calibrating under ASan takes the better part of an hour.
# Not in CI: on two cores the first build takes about 25 minutes and a run
# about 16.
# Environment: CAUSTIC_SANITIZE_JOBS (build jobs, default nproc),
# CAUSTIC_SANITIZE_LOCK (a file held with flock while building, for a
# machine whose builds share its cores), CAUSTIC_SANITIZE_TIMEOUT (seconds
# a binary may run, default 900).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$here/build-asan-tests"
logs="$build/logs"
jobs="${CAUSTIC_SANITIZE_JOBS:-$(nproc 2>/dev/null || echo 2)}"
limit="${CAUSTIC_SANITIZE_TIMEOUT:-900}"

# name  leaks(1: checked)  — one table for the suites this mode runs.
table="
optics_test 1
dispersion_test 1
colour_test 1
scene_test 1
water_test 1
solid_path_test 1
reference_test 1
config_test 1
picture_header_test 1
rate_limit_test 1
h264_level_test 1
room_messages_test 1
signal_message_test 1
receive_bins_test 0
design_test 1
cli_test 0
engine_test 0
glsl_twin_test 0
fidelity_test 0
engine_vs_reference_test 0
stability_trials_test 0
designed_scenes_test 0
"
declare -A leaks=()
chosen=()
while read -r name check; do
  [[ -z $name ]] && continue
  leaks[$name]=$check
  if (($# == 0)) || [[ " $* " == *" $name "* ]]; then chosen+=("$name"); fi
done <<<"$table"
for name in "$@"; do
  [[ -n ${leaks[$name]:-} ]] || { echo "sanitize unit: no suite $name (tools/sanitize_unit.sh lists them)" >&2; exit 2; }
done

locked() {
  if [[ -n ${CAUSTIC_SANITIZE_LOCK:-} ]]; then flock "$CAUSTIC_SANITIZE_LOCK" "$@"; else "$@"; fi
}

mkdir -p "$logs"
echo "== building the unit suites (asan+ubsan) in $build"
flags="-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=undefined,float-cast-overflow -O1 -g1 -D_GLIBCXX_ASSERTIONS"
link="-fsanitize=address,undefined,float-cast-overflow"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-DNDEBUG" -DCMAKE_EXE_LINKER_FLAGS="$link" \
  -DCMAKE_SHARED_LINKER_FLAGS="$link" >"$logs/configure.log" 2>&1 ||
  { cat "$logs/configure.log"; exit 1; }
# causticd and the assets first: the calibrations copied below must be
# newer than the causticd that would otherwise remake them.
locked cmake --build "$build" -j "$jobs" --target causticd assets >"$logs/build.log" 2>&1 ||
  { tail -n 40 "$logs/build.log"; exit 1; }
normal="$here/build/share/causticd"
mine="$build/share/causticd"
for scene in "$mine"/assets/scenes/*.json; do
  [[ $scene == *.calibration.json ]] && continue
  calibration="$normal/assets/scenes/$(basename "$scene" .json).calibration.json"
  [[ -f $calibration ]] && cp "$calibration" "$mine/assets/scenes/"
done
if [[ ! -d $mine/web && -d $normal/web ]]; then cp -r "$normal/web" "$mine/web"; fi
locked cmake --build "$build" -j "$jobs" --target "${chosen[@]}" >>"$logs/build.log" 2>&1 ||
  { tail -n 40 "$logs/build.log"; exit 1; }

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# GLib's slice allocator would keep freed blocks out of ASan's sight.
export G_SLICE=always-malloc
failed=()
for name in "${chosen[@]}"; do
  start=$SECONDS
  # handle_abort: a failed _GLIBCXX_ASSERTIONS check prints its stack too.
  ASAN_OPTIONS="detect_leaks=${leaks[$name]}:handle_abort=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
    timeout "$limit" "$build/tests/$name" >"$logs/$name.log" 2>&1
  status=$?
  printf '%-26s exit %3d  %5d s\n' "$name" "$status" $((SECONDS - start))
  ((status == 0)) || failed+=("$name")
done

# The fuzz targets' seeds and regressions, once each (no fuzzing: tools/fuzz.sh does that).
if ! command -v clang++ >/dev/null 2>&1; then
  echo "== fuzz inputs not replayed: clang++ is not installed (Debian: apt-get install clang libclang-rt-14-dev)"
elif (($# == 0)); then
  fuzz="$build/fuzz"
  if CC=clang CXX=clang++ cmake -S "$here/tests/fuzz" -B "$fuzz" >"$logs/fuzz-configure.log" 2>&1 &&
    locked cmake --build "$fuzz" -j "$jobs" >"$logs/fuzz-build.log" 2>&1; then
    for target in "$fuzz"/fuzz_*; do
      [[ -x $target && -f $target ]] || continue
      name="$(basename "$target")"
      mapfile -t inputs < <(find "$here/tests/fuzz/corpus/${name#fuzz_}" "$here/tests/fuzz/regressions/${name#fuzz_}" \
        -type f 2>/dev/null)
      ((${#inputs[@]})) || continue
      ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" timeout "$limit" "$target" "${inputs[@]}" \
        >"$logs/$name.log" 2>&1
      status=$?
      printf '%-26s exit %3d  %5d inputs\n' "$name" "$status" "${#inputs[@]}"
      ((status == 0)) || failed+=("$name")
    done
  else
    echo "== the fuzz targets did not build (libclang-rt-14-dev?): $logs/fuzz-build.log"
    failed+=(fuzz-build)
  fi
fi

if ((${#failed[@]})); then
  echo "== failed: ${failed[*]} (logs in $logs)"
  exit 1
fi
echo "== clean"
