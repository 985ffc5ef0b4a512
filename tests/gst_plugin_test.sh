#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# causticsrc as a loadable plugin: gst-inspect-1.0 finds libgstcaustic.so
# and lists the documented properties and pad template, the launch lines of
# the element's own doc comment run, and the launch line of docs/api.md
# runs (on the build's scene) and writes a WebM file that decodes back to
# the frames asked for, showing a caustic, not a blank.
#   gst_plugin_test.sh PLUGIN_DIR SCENES_DIR API_MD ELEMENT_SOURCE
set -euo pipefail
plugin_dir="$(realpath "$1")" scenes="$(realpath "$2")" api_md="$(realpath "$3")" element_source="$(realpath "$4")"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
for tool in gst-inspect-1.0 gst-launch-1.0; do
  command -v "$tool" >/dev/null || fail "$tool is missing (Debian package gstreamer1.0-tools)"
done
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export GST_PLUGIN_PATH="$plugin_dir"
export GST_REGISTRY="$out/registry.bin" # a registry of its own: nothing stale
cd "$out"

gst-inspect-1.0 causticsrc >inspect.txt 2>&1 || fail "gst-inspect-1.0 causticsrc: $(cat inspect.txt)"
grep -q "Filename *$plugin_dir/libgstcaustic.so" inspect.txt || fail "not loaded from the plugin file: $(head -30 inspect.txt)"
grep -q "License *LGPL" inspect.txt || fail "no licence"
grep -q "SRC template: 'src'" inspect.txt || fail "no src pad template"
grep -q "format: { (string)RGBA, (string)I420 }" inspect.txt || fail "the formats are not the documented ones"
# Every property docs/api.md documents, and no other.
documented="$(awk '/^Element Properties:/ { p = 1; next } p && /^```/ { exit } p && /^  [a-z]/ { print $1 }' "$api_md" | sort)"
[[ -n "$documented" ]] || fail "no properties found in $api_md"
listed="$(awk '/^Element Properties:/ { p = 1; next } p && /^  [a-z]/ { print $1 }' inspect.txt | sort)"
inherited="blocksize do-timestamp name num-buffers parent typefind automatic-eos"
for prop in $documented; do grep -qx "$prop" <<<"$listed" || fail "gst-inspect does not list \"$prop\""; done
for prop in $listed; do
  grep -qx "$prop" <<<"$documented" || [[ " $inherited " == *" $prop "* ]] || fail "\"$prop\" is not documented in docs/api.md"
done

# The doc comment's launch lines, on the scene this build made: a window's
# sink becomes fakesink and a line without an end gets a few buffers.
ran=0
while read -r doc_line; do
  doc_line="${doc_line//\/usr\/share\/causticd\/assets\/scenes/$scenes}"
  doc_line="${doc_line//autovideosink/fakesink}"
  [[ "$doc_line" == *num-buffers=* ]] || doc_line="${doc_line/causticsrc /causticsrc num-buffers=5 }"
  read -ra words <<<"$doc_line"
  timeout 300 "${words[@]:0:1}" -q "${words[@]:1}" >doc_launch.txt 2>&1 </dev/null ||
    fail "the doc comment's launch line failed: $doc_line: $(cat doc_launch.txt)"
  ran=$((ran + 1))
done < <(sed -n 's/^ \* \(gst-launch-1.0 causticsrc .*\)$/\1/p' "$element_source")
((ran >= 2)) || fail "only $ran launch lines in the doc comment of $element_source"
rm -f out.webm

# The documented launch line, on the scene this build made.
line="$(grep -m1 '^gst-launch-1.0 causticsrc ' "$api_md")" || fail "no launch line in $api_md"
line="${line//\/usr\/share\/causticd\/assets\/scenes/$scenes}"
read -ra words <<<"$line"
timeout 300 "${words[@]:0:1}" -q "${words[@]:1}" >launch.txt 2>&1 || fail "the launch line failed: $line: $(cat launch.txt)"
[[ -s out.webm ]] || fail "no out.webm"
width="$(sed -n 's/.* width=\([0-9]*\) .*/\1/p' <<<"$line")"
height="$(sed -n 's/.* height=\([0-9]*\) .*/\1/p' <<<"$line")"
frames="$(sed -n 's/.* num-buffers=\([0-9]*\) .*/\1/p' <<<"$line")"
gst-launch-1.0 -q filesrc location=out.webm ! matroskademux ! vp8dec ! video/x-raw,format=I420 ! filesink location=out.i420 \
  >decode.txt 2>&1 || fail "out.webm does not decode: $(cat decode.txt)"
frame_bytes=$((width * height * 3 / 2))
size="$(stat -c %s out.i420)"
((size == frames * frame_bytes)) || fail "decoded $size bytes, not $frames frames of ${width}x$height"
# The last frame's luma: a caustic has bright and dark parts, a blank frame one value.
tail -c "$frame_bytes" out.i420 >last.i420
levels="$(head -c $((width * height)) last.i420 | od -An -tu1 -v | tr -s ' ' '\n' | sort -un | wc -l)"
((levels > 32)) || fail "the last frame has only $levels luma levels"
echo "causticsrc from $plugin_dir: $frames frames of ${width}x$height in out.webm ($(stat -c %s out.webm) bytes), $levels luma levels"
