#!/usr/bin/env bash
# Command one: install dependencies (Debian 12, as root), build Release, start laptrainer on the
# default scenario. Without a display laptrainer says so, loads and checks the scenario without a
# window and prints a summary.
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/install-deps.sh
cmake --preset release
cmake --build --preset release --parallel "$(nproc)"
exec ./build/release/bin/laptrainer "$@"
