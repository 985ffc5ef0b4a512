#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Builds the libFuzzer targets of tests/fuzz (clang, ASan, UBSan) in
# build-fuzz/ and runs each of them:
#   tools/fuzz.sh [SECONDS]     # default 30 s per target; 3600 for a long run
# First every file of tests/fuzz/regressions/<target>/ is replayed once, then
# the target fuzzes for SECONDS, starting from a copy of its seed corpus
# (tests/fuzz/corpus/<target>/), so the committed seeds never change.
# Crash, leak and timeout inputs land in build-fuzz/crashes/, logs in
# build-fuzz/logs/. Exits 1 on any crash or sanitizer report, 77 when
# clang or libFuzzer is missing (CTest counts that as skipped).
# Environment: CAUSTIC_FUZZ_BUILD_DIR (default build-fuzz), CAUSTIC_FUZZ_JOBS
# (build jobs, default nproc), CAUSTIC_FUZZ_TARGETS (space-separated subset),
# CAUSTIC_FUZZ_SEED and CAUSTIC_FUZZ_RUNS: with both set, each target runs
# that many inputs from that seed (SECONDS then only caps it), so a test run
# explores the same inputs every time and its verdict is reproducible; the
# long, time-bounded runs leave them unset and explore anew.
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CAUSTIC_FUZZ_BUILD_DIR:-$here/build-fuzz}"
seconds="${1:-30}"
fuzz_dir="$here/tests/fuzz"
if ! [[ $seconds =~ ^[0-9]+$ ]] || ((seconds < 1)); then
  echo "usage: tools/fuzz.sh [SECONDS]" >&2
  exit 2
fi

# target  max_len  dictionary: lengths fit what the parser takes in real use
# (a patch or scene of a few KiB, an SDP answer, a URL path).
table="
json_text   4096 json
scene       4096 scene
patch       2048 scene
obj         8192 obj
config      2048 config
signal      8192 signal
static_path 512  static_path
request_head 4096 request_head
picture_header 256 -
png         2048 -
"

for tool in clang clang++ cmake; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "fuzz: skipped, $tool is not installed (Debian: apt-get install clang libclang-rt-14-dev cmake)"
    exit 77
  fi
done
mkdir -p "$build"
# libFuzzer and the sanitizer runtimes come apart from clang itself
# (libclang-rt-14-dev on Debian 12): link a trivial fuzzer to find out.
probe="$build/probe"
if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' |
  clang++ -x c++ - -fsanitize=fuzzer,address,undefined -o "$probe" >"$build/probe.log" 2>&1; then
  echo "fuzz: skipped, clang++ cannot link -fsanitize=fuzzer,address,undefined (Debian: apt-get install libclang-rt-14-dev):"
  tail -n 3 "$build/probe.log"
  exit 77
fi

echo "== building the fuzz targets in $build"
build_start=$SECONDS
# Configured every time (a second or two): targets whose sources appear later
# are picked up, and the compilers are fixed on the first run only.
CC=clang CXX=clang++ cmake -S "$fuzz_dir" -B "$build" >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "${CAUSTIC_FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}" >"$build/build.log" 2>&1 ||
  { tail -n 60 "$build/build.log"; exit 1; }
echo "== built in $((SECONDS - build_start)) s"

mkdir -p "$build/crashes" "$build/logs"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# GLib's slice allocator would hide heap errors from ASan.
export G_SLICE=always-malloc

failed=()
summary=()
while read -r target max_len dict; do
  [[ -z $target ]] && continue
  if [[ -n ${CAUSTIC_FUZZ_TARGETS:-} && " $CAUSTIC_FUZZ_TARGETS " != *" $target "* ]]; then continue; fi
  bin="$build/fuzz_$target"
  if [[ ! -x $bin ]]; then
    summary+=("$(printf '%-12s not built (its source is not there)' "$target")")
    continue
  fi
  options=(-rss_limit_mb=1024 -timeout=10 -max_len="$max_len" "-artifact_prefix=$build/crashes/$target-")
  [[ $dict != - && -f $fuzz_dir/dicts/$dict.dict ]] && options+=("-dict=$fuzz_dir/dicts/$dict.dict")

  # Replays: libFuzzer runs each file given by name once, without fuzzing.
  regressions=()
  if [[ -d $fuzz_dir/regressions/$target ]]; then
    while IFS= read -r -d '' f; do regressions+=("$f"); done < <(find "$fuzz_dir/regressions/$target" -type f -print0 | sort -z)
  fi
  if ((${#regressions[@]})); then
    if ! "$bin" "${options[@]}" "${regressions[@]}" </dev/null >"$build/logs/$target-regressions.log" 2>&1; then
      echo "== $target: a regression input fails again; see $build/logs/$target-regressions.log"
      grep -E 'Running:|ERROR|CRITICAL|SUMMARY|runtime error|invariant' "$build/logs/$target-regressions.log" | head -n 20
      failed+=("$target (regressions)")
    fi
  fi

  work="$build/work/$target"
  rm -rf "$work"
  mkdir -p "$work/corpus"
  [[ -d $fuzz_dir/corpus/$target ]] && cp -R "$fuzz_dir/corpus/$target/." "$work/corpus/"
  log="$build/logs/$target.log"
  echo "== $target: fuzzing for ${CAUSTIC_FUZZ_RUNS:+$CAUSTIC_FUZZ_RUNS inputs, at most }${seconds} s"
  # Only here: given files, -runs would replay each of them that many times.
  [[ -n ${CAUSTIC_FUZZ_SEED:-} ]] && options+=("-seed=$CAUSTIC_FUZZ_SEED")
  [[ -n ${CAUSTIC_FUZZ_RUNS:-} ]] && options+=("-runs=$CAUSTIC_FUZZ_RUNS")
  "$bin" "${options[@]}" -max_total_time="$seconds" -print_final_stats=1 "$work/corpus" </dev/null >"$log" 2>&1
  rc=$?
  last="$(grep -E '^#[0-9]+' "$log" | tail -n 1)"
  corpus_files="$(find "$work/corpus" -type f | wc -l)"
  summary+=("$(printf '%-12s rc=%-3s %s  [corpus %s files]' "$target" "$rc" "${last:-no stats}" "$corpus_files")")
  if ((rc != 0)) || grep -qE '^==[0-9]+==ERROR|runtime error:|^SUMMARY: |-CRITICAL \*\*|-ERROR \*\*' "$log"; then
    echo "== $target: FAILED (exit $rc); log: $log"
    grep -E 'ERROR|CRITICAL|SUMMARY|runtime error|invariant|Test unit written|^ +#[0-9]+ ' "$log" | head -n 30
    failed+=("$target")
  fi
done <<<"$table"

echo "== summary"
printf '%s\n' "${summary[@]}"
if ((${#failed[@]})); then
  echo "fuzz: FAILED: ${failed[*]}; reproduce with $build/fuzz_<target> <file>; inputs are in $build/crashes/"
  exit 1
fi
echo "fuzz: no crash"
