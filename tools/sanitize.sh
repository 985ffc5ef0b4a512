#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Builds causticd with a sanitizer and runs the session-cycle bench
# (bench/session_cycles.cpp) against it:
#   tools/sanitize.sh asan [CYCLES]   # ASan + UBSan + LSan, default 1000 cycles
#   tools/sanitize.sh tsan [CYCLES]   # ThreadSanitizer, default 1 cycle
#   tools/sanitize.sh unit [TEST...]  # the unit suites under ASan + UBSan
#                                     # (tools/sanitize_unit.sh; default all)
# Builds incrementally in build-asan/ or build-tsan/ (only causticd and the
# bench, tests off). The server's stderr (its log and every sanitizer
# report) goes to build-<kind>/logs/server-<time>.log, the bench's table to
# the terminal and build-<kind>/logs/cycles-<time>.json.
# Exits 1 on any ASan or UBSan error, any leak at exit but those of
# tools/lsan.supp and GLib's quark tables, any TSan report with an access in
# src/ (docs/reliability-sanitizers.md lists the known ones), a failed
# cycle, or growth of RSS, descriptors or threads (the bench's own checks).
# Too slow for CI: on two cores about 0.6 s a cycle under ASan and 6 s
# under TSan, plus a minute or two to start and to check for leaks.
# Environment: CAUSTIC_SANITIZE_JOBS (build jobs, default nproc),
# CAUSTIC_TSAN_SYNC=0 (a TSan run without tools/tsan_glib_sync.cpp, to see
# what TSan reports when GLib's locks are hidden from it),
# CAUSTICD_DATA_DIR (data folder; default: build/share/causticd of the
# normal build, else the sanitized build's own, without calibrations).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
kind="${1:-}"
case "$kind" in
  unit)
    shift
    exec "$here/tools/sanitize_unit.sh" "$@"
    ;;
  asan)
    cycles="${2:-1000}"
    # -O1 -g1: line tables for the stacks at a fraction of -O2 -g's compile time.
    flags="-fsanitize=address,undefined -fno-omit-frame-pointer -O1 -g1"
    link="-fsanitize=address,undefined"
    # Leaks are checked when the server exits (LSan's exit status 23).
    export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:exitcode=23${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
    sanitizer_status=23
    # report_objects: each leaked block's address and size, which is how
    # GLib's quark tables are told apart from other g_malloc blocks below.
    export LSAN_OPTIONS="suppressions=$here/tools/lsan.supp:print_suppressions=1:report_objects=1${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
    # GLib's slice allocator would keep freed GObjects in its own magazines,
    # out of LSan's sight: plain malloc makes a leaked GObject a leak.
    export G_SLICE=always-malloc G_DEBUG=gc-friendly
    # ASan holds freed memory in quarantine (256 MiB) before reusing it, so
    # RSS climbs for hundreds of cycles whatever the server does: the 20 MiB
    # RSS check belongs to the normal build; here only gross growth fails.
    timeouts=(--frame-timeout 60 --idle-timeout 60 --start-timeout 300 --exit-timeout 300 --rss-slack-mib 300)
    ;;
  tsan)
    cycles="${2:-1}"
    flags="-fsanitize=thread -O1 -g1"
    link="-fsanitize=thread"
    export TSAN_OPTIONS="halt_on_error=0:report_signal_unsafe=0:second_deadlock_stack=1:exitcode=66${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
    sanitizer_status=66
    # Plain malloc instead of GLib's slices: a slice reused by another thread
    # through the slice allocator's own (invisible) lock reads as a race.
    export G_SLICE=always-malloc
    timeouts=(--frame-timeout 300 --idle-timeout 300 --start-timeout 600 --exit-timeout 300)
    ;;
  *)
    echo "usage: tools/sanitize.sh asan|tsan [CYCLES] | unit [TEST...]" >&2
    exit 2
    ;;
esac
if ! [[ $cycles =~ ^[0-9]+$ ]] || ((cycles < 1)); then
  echo "usage: tools/sanitize.sh asan|tsan [CYCLES] | unit [TEST...]" >&2
  exit 2
fi

build="$here/build-$kind"
logs="$build/logs"
mkdir -p "$logs"
jobs="${CAUSTIC_SANITIZE_JOBS:-$(nproc 2>/dev/null || echo 2)}"
echo "== building causticd ($kind) in $build"
# The sanitizer flags stand in for the build type's own (-O2 -g would double the compile time).
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAUSTICD_BUILD_TESTS=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-DNDEBUG" \
  -DCMAKE_EXE_LINKER_FLAGS="$link" -DCMAKE_SHARED_LINKER_FLAGS="$link" >"$logs/configure.log" 2>&1 ||
  { cat "$logs/configure.log"; exit 1; }
cmake --build "$build" -j "$jobs" --target causticd session_cycles >"$logs/build.log" 2>&1 ||
  { tail -n 40 "$logs/build.log"; exit 1; }
if [[ $kind == tsan && ${CAUSTIC_TSAN_SYNC:-1} != 0 ]]; then
  # GLib's locks and GStreamer's reference counts, made visible to TSan
  # (tools/tsan_glib_sync.cpp), preloaded.
  sync_lib="$build/lib/libtsan_glib_sync.so"
  mkdir -p "$build/lib"
  # shellcheck disable=SC2046 # pkg-config's flags are words
  "${CXX:-c++}" -std=c++20 -shared -fPIC -O2 -g $(pkg-config --cflags glib-2.0) \
    "$here/tools/tsan_glib_sync.cpp" -o "$sync_lib" -l:libtsan.so.2 -ldl >>"$logs/build.log" 2>&1 ||
    { tail -n 20 "$logs/build.log"; exit 1; }
  # Into the server alone: the bench is built without a sanitizer.
  server="$build/bin/causticd-glib-sync"
  printf '#!/bin/sh\nLD_PRELOAD=%q exec %q "$@"\n' "$sync_lib" "$build/bin/causticd" >"$server"
  chmod +x "$server"
fi
# The data (meshes, calibrations, web files) does not depend on the
# sanitizer: the normal build's is used when there is one; otherwise the
# meshes and web files are made here, without calibrations, which would
# run the reference tracer under the sanitizer.
if [[ -z ${CAUSTICD_DATA_DIR:-} && -d $here/build/share/causticd/assets ]]; then
  export CAUSTICD_DATA_DIR="$here/build/share/causticd"
elif [[ -z ${CAUSTICD_DATA_DIR:-} ]]; then
  cmake --build "$build" -j "$jobs" --target assets web >>"$logs/build.log" 2>&1 ||
    { tail -n 40 "$logs/build.log"; exit 1; }
fi

stamp="$(date +%Y%m%d-%H%M%S)"
server_log="$logs/server-$stamp.log"
report="$logs/cycles-$stamp.json"
echo "== $cycles cycles under $kind; server log $server_log"
"$build/bin/session_cycles" --causticd "${server:-$build/bin/causticd}" --cycles "$cycles" --report "$report" \
  --sanitizer-exit-status "$sanitizer_status" "${timeouts[@]}" 2>"$server_log"
bench=$?

# Sanitizer reports are read from the log, whatever the exit status said:
# TSan goes on after a race, UBSan may not halt.
project="$logs/project-reports-$stamp.txt"
if [[ $kind == asan ]]; then
  # GLib leaks its quark table on purpose each time it grows (gquark.c:
  # lock-free readers may still hold the old one): the 2048-pointer table
  # (16384 bytes) when the 2049th quark is made, the 4096-pointer one (32768)
  # at the 4097th, and so on. webrtcbin makes one quark per offer (the SSRC
  # that names its RTX map's field, with do-nack), so about 760 sessions
  # leak the second table. LSan merges every g_malloc block into one report
  # (GLib's missing frame pointers hide the callers); among its objects,
  # one block of each size 16384*k, k = 1, 2, ..., K, is a quark table. Any other
  # leak, and every ASan or UBSan error, counts.
  awk -v out="$project" '
    function flush(   i, k, n, top, rest, count) {
      if (!inleak) return
      # Tables 1..top, each one block (LSan lists objects by address).
      for (i = 1; i <= objs; i++) if (glib && size[i] % 16384 == 0) count[size[i] / 16384]++
      for (top = 0; count[top + 1] == 1; top++) {}
      rest = ""; n = 0
      for (i = 1; i <= objs; i++) {
        k = size[i] / 16384
        if (glib && size[i] % 16384 == 0 && k <= top) known++
        else { rest = rest "\n" obj[i]; n++ }
      }
      if (objs == 0 || n > 0) { print block (objs ? "\nObjects not allowed:" rest : "") "\n" > out; counted++ }
      inleak = 0
    }
    /^(Direct|Indirect) leak of/ { flush(); block = $0; frames = 0; objs = 0; inleak = 1; direct = /^Direct/; next }
    inleak && /^ +#[0-9]+ / { block = block "\n" $0; frames++; last = $0; next }
    inleak && /^0x[0-9a-f]+ \([0-9]+ bytes\)/ {
      glib = direct && frames == 2 && last ~ / in g_malloc \(.*libglib-2\.0\.so/
      obj[++objs] = $0; s = $2; sub(/^\(/, "", s); size[objs] = s + 0; next
    }
    inleak && /^(Objects leaked above:)?$/ { next }
    inleak { flush() }
    /ERROR: AddressSanitizer|runtime error: / { print > out; counted++ }
    END { flush(); printf "%d %d\n", counted + 0, known + 0 }' "$server_log" >"$logs/counts"
  read -r counted known <"$logs/counts"
  echo "== LSan: $known GLib quark table(s) allowed; project-relevant reports: $counted"
else
  # GLib's GMutex and GCond are futexes TSan cannot see, so every buffer or
  # message handed between GStreamer threads can read as a race
  # (tools/tsan_glib_sync.cpp shows TSan most of them, not those inside
  # GLib itself). A race counts when one of its two accesses is made by the
  # project's own code (src/): its innermost frame is there, or it is a C
  # library call TSan intercepts (malloc, free, memcpy) made from there. A
  # race between two accesses that a library makes to its own memory
  # (GLib's queue links, GIO's sockets) under our calls is the library's.
  # Any other kind of report counts with a frame in src/ anywhere.
  awk -v src="$here/src/" -v out="$project" '
    /^WARNING: ThreadSanitizer/ { block = $0; ours = 0; access = 0; inrep = 1; race = /data race/; next }
    inrep && /^SUMMARY: ThreadSanitizer/ {
      block = block "\n" $0
      if (ours) { print block "\n" > out; counted++ } else other++
      inrep = 0; next
    }
    inrep {
      block = block "\n" $0
      if ($0 ~ /^  [A-Z]/) { access = ($0 ~ /^  (Previous )?(atomic )?([Rr]ead|[Ww]rite) of size/); via_libc = 0 }
      if (!race) { if (index($0, src)) ours = 1; next }
      if (access && $0 ~ /^    #0 /) { if (index($0, src)) ours = 1; via_libc = ($0 ~ /libsanitizer|libtsan/) }
      else if (access && via_libc && $0 ~ /^    #1 /) { if (index($0, src)) ours = 1; via_libc = 0 }
    }
    END { printf "%d %d\n", counted + 0, other + 0 }' "$server_log" >"$logs/counts"
  read -r counted known <"$logs/counts"
  echo "== TSan: $known report(s) within third-party code only; reports with an access in src/: $counted"
fi
if ((counted > 0)); then
  echo "== project-relevant reports in $project:"
  grep -E '^(SUMMARY|Direct|Indirect|.*ERROR: |.*runtime error)' "$project" | sort | uniq -c | sort -rn | head -n 20
fi
echo "== bench exit status $bench (log: $server_log)"
if ((bench != 0 || counted != 0)); then exit 1; fi
echo "== clean"
