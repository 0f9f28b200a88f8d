#!/usr/bin/env bash
# Configures (Release) and builds into build/: the targets named on the
# command line (scripts/build.sh pathtracer grader), or every target.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
# Through ccache where it is installed (CMakeLists.txt, PT_CCACHE).
ccache=OFF
command -v ccache >/dev/null 2>&1 && ccache=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPT_CCACHE=$ccache >/dev/null
if [ $# -gt 0 ]; then
  cmake --build build -j "$jobs" --target "$@"
else
  cmake --build build -j "$jobs"
fi
