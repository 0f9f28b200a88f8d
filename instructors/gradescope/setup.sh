#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image
# (the zip is unpacked in /autograder/source). It installs the packages,
# then builds the grader and a starter-kit pathtracer in /autograder/pt, so
# that each submission's build recompiles only its stages/.
#
# Environment (for testing outside Gradescope):
#   AUTOGRADER_ROOT=DIR     instead of /autograder
#   AUTOGRADER_SKIP_APT=1   do not install packages (they are there already)
#   AUTOGRADER_GRADER_ONLY=1  build only the grader (instructors/batch/grade_folder.sh)
#   AUTOGRADER_SKIP_REFERENCE_CHECK=1  do not check the references
set -euo pipefail

source_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${AUTOGRADER_ROOT:-/autograder}
pt=$root/pt
jobs=$(nproc 2>/dev/null || echo 2)

packages=(build-essential cmake python3 libtinyxml2-dev liblodepng-dev libcli11-dev libopenexr-dev)
if [ "${AUTOGRADER_SKIP_APT:-0}" != 1 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update
  apt-get install -y --no-install-recommends "${packages[@]}"
fi

# The tree submissions are built in: the starter kit; run_autograder puts
# each submission's stages/ over it.
rm -rf "$pt"
mkdir -p "$pt/bin"
cp -R "$source_dir/project" "$pt/tree"

cmake -S "$pt/tree" -B "$pt/build" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF
targets=(grader pathtracer)
[ "${AUTOGRADER_GRADER_ONLY:-0}" = 1 ] && targets=(grader)
cmake --build "$pt/build" --target "${targets[@]}" -j "$jobs"
# The grader lives outside the build folder submissions are built in.
cp "$pt/build/bin/grader" "$pt/bin/grader"
"$pt/bin/grader" --help >/dev/null

# Every case's reference must load and match its case's definition: a
# "pathtracer" that renders nothing fails every case, and a missing or
# stale reference makes the case an error (exit status 2). Takes a second.
if [ "${AUTOGRADER_SKIP_REFERENCE_CHECK:-0}" != 1 ] && ! grep -q '^reference check: off' "$source_dir/VERSION" 2>/dev/null; then
  check=$(mktemp -d)
  rc=0
  "$pt/bin/grader" run --pathtracer "$(type -P true)" -q -o "$check/out" \
    --cases "$source_dir/project/grader/cases.txt" --references "$source_dir/project/reference_images" \
    --scenes "$source_dir/project/scenes" >"$check/log" 2>&1 || rc=$?
  if [ "$rc" -ne 1 ]; then
    grep -w error "$check/out/report.txt" 2>/dev/null || cat "$check/log"
    echo "setup: error: the references do not fit the cases (grader exit status $rc): remake them and the zip" >&2
    exit 1
  fi
  rm -rf "$check"
  echo "setup: every case has its reference"
fi
echo "setup: grader in $pt/bin/grader; build folder $pt/build"
