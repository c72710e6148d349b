#!/usr/bin/env bash
# The installable package, end to end (issue 26): builds the .deb from a Release build tree
# (cpack), checks it with lintian (no errors), installs it with dpkg into a temporary root, runs
# the installed binaries there (validate the installed default scenario, play the expert's
# scripts from the installed scripts, the window's screenshot under Xvfb, the window finding its
# scenario beside itself, the window started as the desktop menu starts it), removes it with
# dpkg and checks nothing of it is left.
# Usage: packaging/test-package.sh BUILD_DIR
set -euo pipefail
build="$(cd "${1:?usage: test-package.sh BUILD_DIR}" && pwd)"
cd "$build"
rm -rf packages
cpack -G DEB > cpack.log || { cat cpack.log; exit 1; }
deb="$(ls packages/laptrainer_*.deb)"
echo "package: $deb ($(du -h "$deb" | cut -f1))"
# Errors fail; warnings and informational tags are listed for the reader.
lintian --fail-on error --tag-display-limit 0 "$deb"

root="$(mktemp -d)"
trap 'rm -rf "$root"' EXIT
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
touch "$root/var/lib/dpkg/status" "$root/var/lib/dpkg/available"
# Dependencies are the machine's (this root has no other packages): --force-depends.
dpkg --root="$root" --force-depends --force-not-root --force-bad-path --log=/dev/null -i "$deb" \
  > "$root/dpkg.log" 2>&1 || { cat "$root/dpkg.log"; exit 1; }

share="$root/usr/share/laptrainer"
"$root/usr/bin/laptrainer-cli" validate --scenario "$share/scenarios/default.yaml"
out="$("$root/usr/bin/laptrainer-cli" run --scenario "$share/scenarios/default.yaml" \
  --left "scripted:$share/scenarios/scripts/default/expert_left.csv" \
  --right "scripted:$share/scenarios/scripts/default/expert_right.csv" --fast --duration 60 \
  2>/dev/null)"
grep -q '"result": "success"' <<< "$out" || { echo "the installed expert run did not succeed"; exit 1; }
# Without a display the window says which scenario it opened: the installed one.
headless="$(env -u DISPLAY -u WAYLAND_DISPLAY "$root/usr/bin/laptrainer")"
grep -qF "$share/scenarios/default.yaml" <<< "$headless" ||
  { echo "the installed laptrainer did not open its own default scenario:"; echo "$headless"; exit 1; }
xvfb-run -a -s "-screen 0 1280x1024x24" "$root/usr/bin/laptrainer" \
  --screenshot "$root/shot.png" --frames 5
test -s "$root/shot.png"
test -f "$root/usr/share/icons/hicolor/scalable/apps/laptrainer.svg"
# As the desktop menu starts it: the entry's Exec line, found on the PATH, with no arguments; the
# window must open and stay open (timeout's 124 after 8 s), with a home of its own.
entry="$root/usr/share/applications/laptrainer.desktop"
test -f "$entry"
exec_line="$(sed -n 's/^Exec=//p' "$entry")"
[ -n "$exec_line" ] || { echo "$entry has no Exec line"; exit 1; }
mkdir -p "$root/home"
status=0
HOME="$root/home" PATH="$root/usr/bin:$PATH" xvfb-run -a -s "-screen 0 1280x1024x24" \
  timeout 8 sh -c "$exec_line" > "$root/menu.log" 2>&1 || status=$?
if [ "$status" -ne 124 ]; then
  echo "the desktop entry's '$exec_line' ended (exit $status) instead of showing the window:"
  cat "$root/menu.log"
  exit 1
fi

dpkg --root="$root" --force-not-root --force-bad-path --log=/dev/null -r laptrainer
if [ -d "$root/usr" ] && [ -n "$(find "$root/usr" -type f)" ]; then
  echo "files left after removal:"
  find "$root/usr" -type f
  exit 1
fi
echo "package ok: lintian clean of errors, installed, ran, removed"
