#!/usr/bin/env bash
# Command one: install dependencies (Debian 12, as root), build Release, start laptrainer on the
# default scenario. Without a display laptrainer says so and runs the scenario headless.
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/install-deps.sh
cmake --preset release
cmake --build --preset release --parallel "$(nproc)"
exec ./build/release/bin/laptrainer "$@"
