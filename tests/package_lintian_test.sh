#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The Debian package passes lintian without errors, and its control data
# say what an operator relies on: the configuration is ucf's, not a dpkg
# conffile (whose question stops a non-interactive upgrade), the
# run-time dependencies come from dpkg-shlibdeps plus the plugins loaded at
# run time, and the plugin file is where GStreamer looks.
#   package_lintian_test.sh PACKAGE.deb
set -euo pipefail
deb="$1"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
[[ -f "$deb" ]] || fail "no package at $deb"
command -v lintian >/dev/null || fail "lintian is missing (Debian package lintian)"
echo "== lintian $(basename "$deb")"
# Errors fail the test; warnings and information are printed for a reader.
lintian --fail-on error --display-info --tag-display-limit 0 "$deb" | tee "${TMPDIR:-/tmp}/lintian.$$" ||
  fail "lintian reports errors"
# Warnings that are the package's to mend: maintainer scripts go through
# deb-systemd-invoke (which asks policy-rc.d), not systemctl.
if grep -E 'maintainer-script-calls-systemctl' "${TMPDIR:-/tmp}/lintian.$$"; then
  rm -f "${TMPDIR:-/tmp}/lintian.$$"
  fail "lintian: a maintainer script calls systemctl"
fi
rm -f "${TMPDIR:-/tmp}/lintian.$$"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
for needed in libc6 libgstreamer1.0-0 libsoup-3.0-0 libembree3-3 gstreamer1.0-plugins-bad gstreamer1.0-nice libgl1-mesa-dri ucf; do
  grep -q "\b$needed\b" <<<"$depends" || fail "Depends lacks $needed"
done
conffiles="$(dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles 2>/dev/null || true)"
[[ -z "$conffiles" ]] || fail "the package has dpkg conffiles: $conffiles"
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./postinst | grep -q '^ *ucf /usr/share/causticd/causticd.conf ' ||
  fail "postinst does not hand causticd.conf to ucf"
contents="$(dpkg-deb -c "$deb")"
grep -q ' ./etc/causticd/causticd.conf$' <<<"$contents" && fail "the package ships /etc/causticd/causticd.conf (a dpkg conffile)"
for file in ./usr/bin/causticd ./usr/share/causticd/causticd.conf ./usr/lib/systemd/system/causticd.service \
  ./usr/lib/systemd/system/causticd@.service ./usr/lib/systemd/system/causticd-janus.service \
  ./usr/share/causticd/janus/setup-broadcast ./usr/lib/sysusers.d/causticd.conf \
  "./usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)/gstreamer-1.0/libgstcaustic.so" \
  ./usr/share/causticd/web/index.html ./usr/share/doc/causticd/copyright ./usr/share/doc/causticd/changelog.gz; do
  grep -q " $file\$" <<<"$contents" || fail "the package lacks $file"
done
echo "ok: $(basename "$deb") ($(stat -c %s "$deb") bytes)"
