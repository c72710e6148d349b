#!/usr/bin/env bash
# Renders the scenario chooser's preview of every scenario (scenarios/previews/<stem>.png): the
# operative field as `laptrainer --screenshot --no-hud` draws it (without the heads-up display),
# 640 x 360, after 30 frames of the session (the tools at home, the organs settled). Run after
# changing a scenario or how the field is drawn; needs a display, or Xvfb (used when DISPLAY is
# unset).
#   bash app/make-previews.sh [path/to/laptrainer]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
app="${1:-$here/build/release/bin/laptrainer}"
out="$here/scenarios/previews"
mkdir -p "$out"
run=()
if [ -z "${DISPLAY:-}" ]; then run=(xvfb-run -a -s "-screen 0 1280x1024x24"); fi
for scenario in "$here"/scenarios/*.yaml; do
  stem="$(basename "$scenario" .yaml)"
  "${run[@]}" "$app" --scenario "$scenario" --size 640x360 --frames 30 --no-hud \
    --screenshot "$out/$stem.png" > /dev/null
  echo "$out/$stem.png"
done
