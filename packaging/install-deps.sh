#!/usr/bin/env bash
# Installs every build, run and test dependency of laptrainer from Debian 12 packages.
# Idempotent: packages already present are skipped, and `apt-get update` runs at most once per call.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git clang-format clang-tidy
  # the asan build and the fuzz targets (tests/fuzz): clang with libFuzzer
  clang-14 libfuzzer-14-dev
  # libraries (see docs/architecture.md for which folder may use which)
  libeigen3-dev libopenmesh-dev libspectra-dev
  libyaml-cpp-dev libtinygltf-dev nlohmann-json3-dev libstb-dev zlib1g-dev libsqlite3-dev
  libusb-1.0-0-dev
  qt6-base-dev libqt6opengl6-dev qt6-charts-dev libvtk9-dev
  # the training-record database (app/store): Qt SQL's SQLite and PostgreSQL drivers, and the
  # PostgreSQL server its tests start a private cluster of (tests/app/store/postgres_fixture.sh)
  libqt6sql6-sqlite libqt6sql6-psql postgresql
  # tests and benchmarks
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  # headless display for GUI tests and screenshots
  xvfb xauth libgl1-mesa-dri mesa-utils
  # the PDF reports are checked by rendering them (pdftoppm) and reading their text (pdftotext);
  # the .deb is checked by lintian
  poppler-utils lintian
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages: ${missing[*]}" >&2
    echo "install-deps: run this script as root (or install sudo) to install them" >&2
    exit 1
  fi
fi

echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
echo "install-deps: done"
