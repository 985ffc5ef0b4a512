#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Figures of docs/design.md: designs benchmark targets with `causticd design`
# (engine check and reference tracer) and prints one table row per run.
# Usage: bench/design_bench.sh BUILD_DIR OUT_DIR TARGET_DIR
#   TARGET_DIR holds cat.png, camera.png, astronaut.png (photographs) and
#   logo.pgm, silhouette.pgm (bench/design_targets.py writes these two).
set -euo pipefail
build=$1 out=$2 targets=$3
mkdir -p "$out"
run() {  # name file resolution [extra flags]
  local name=$1 file=$2 n=$3; shift 3
  "$build/bin/causticd" design --target "$targets/$file" -o "$out/$name-$n.obj" --scene-out "$out/$name-$n.json" \
    --resolution "$n" --verify --photons 16000000 --report "$out/$name-$n.report.json" \
    --side-by-side "$out/$name-$n.png" "$@" > "$out/$name-$n.log"
  python3 - "$out/$name-$n.report.json" "$name" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
e, f = r["engine"], r["reference"]
print(f"| {sys.argv[2]} | {r['resolution']} | {r['design_seconds']:.2f} s | {r['seconds_total']:.2f} s | "
      f"{r['relief_mm']:.1f} mm, {r['max_slope_deg']:.0f}° | {r['tir_vertices']} | "
      f"{e['ssim']:.3f}, {100 * e['relative_l1']:.2f}% | {f['ssim']:.3f}, {100 * f['relative_l1']:.2f}% | "
      f"{100 * e['leak']:.2f}% ({100 * e['target_leak']:.2f}%) |")
PY
}
echo "| target | N | design | with engine check | relief, max slope | TIR | engine SSIM, L1 | reference SSIM, L1 | light on black (target) |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for n in 256 512 1024; do run cat cat.png $n; done
run camera camera.png 512
run astronaut astronaut.png 512
run logo logo.pgm 512
run silhouette silhouette.pgm 512
run logo-regular logo.pgm 512 --regular-grid
