#!/usr/bin/env bash
# Checks one part: builds that part's tests (and the renderer they run; no
# other test, no viewer), then runs them.
#   scripts/check.sh N [ctest options...]     e.g. scripts/check.sh 6
# N is the part, 1 to 9; further arguments go to ctest (e.g. -R sphere,
# --stop-on-failure). Exit status: ctest's (0 when every test of the part
# passed), 1 as well when no test of the part ran, 2 for a bad argument.
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: scripts/check.sh PART [ctest options...]   (PART: 1 to 9, e.g. scripts/check.sh 6)"
[ $# -ge 1 ] || { echo "$usage" >&2; exit 2; }
part=$1
shift
[[ "$part" =~ ^[1-9]$ ]] || { echo "check: '$part' is not a part number; $usage" >&2; exit 2; }
label=part$part

scripts/setup.sh --build-only
echo "check: building part $part's tests (target ${label}_tests) ..."
scripts/build.sh "${label}_tests"

# ctest -L takes a regular expression: anchored, so that it selects this
# label alone. A selection that holds no test is an error, never a pass.
count=$(ctest --test-dir build -N -L "^${label}\$" "$@" | sed -n 's/^Total Tests: *//p')
if [ "${count:-0}" -eq 0 ]; then
  echo "check: FAILED: no test of part $part was found in build/${*:+ with $*}, so nothing was checked" >&2
  exit 1
fi
echo "check: running part $part's $count tests ..."
status=0
ctest --test-dir build -L "^${label}\$" --no-tests=error --output-on-failure "$@" || status=$?
if [ "$status" -eq 0 ]; then
  echo "check: part $part: every test passed"
else
  echo "check: part $part: some tests failed (their output is above; ctest exit status $status)"
fi
exit "$status"
