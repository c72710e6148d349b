#!/usr/bin/env bash
# clang-tidy over every library source with the repository's .clang-tidy, warnings as errors
# (the ctest label `lint`; about 13 CPU-minutes). Run it before committing C++ changes; the CI run
# (packaging/test.sh) leaves it out for time and checks clang-format only.
#
#   bash packaging/lint.sh        (after command two, or any Release configure with tests)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build/release/compile_commands.json ]; then
  cmake --preset release -DLAP_WARNINGS_AS_ERRORS=ON -DLAP_BUILD_TESTS=ON
fi
# clang-tidy reads compile_commands.json; the moc and autogen headers must exist for app/.
cmake --build --preset release --parallel "$(nproc)"
ctest --preset release --parallel "$(nproc)" -L lint
