#!/usr/bin/env bash
# The whole test suite: install what is missing, build, run every test
# through ctest. Extra arguments go to ctest (e.g. -L part1).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" "$@"
