#!/usr/bin/env bash
# The grader's self-check: builds the renderer once per mutant of
# grader/mutants.txt (one classic student bug each, -DPT_MUTANT=<name>),
# grades each build on its part's cases, grades the reference build and the
# starter kit on every case, and writes the table to grader/tables/mutants.md.
#
#   grader/grade_mutants.sh [--build-root DIR] [--table FILE] [-j N] [--only NAME]...
#
# A mutant is caught when at least one case of its part fails. Slow (one
# build per mutant, about a minute each on 2 cores): run it on purpose, not
# in the test suite. Exit status: 0 when the reference passes everything,
# the starter kit scores at most 10 % and every mutant is caught; 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build_root="$root/build/mutants"
table="$root/grader/tables/mutants.md"
jobs=$(nproc 2>/dev/null || echo 2)
only=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build-root) build_root=$2; shift 2 ;;
    --table) table=$2; shift 2 ;;
    -j) jobs=$2; shift 2 ;;
    --only) only+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "grade_mutants.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
mkdir -p "$build_root"
grader="$root/build/bin/grader"
[ -x "$grader" ] || { echo "grade_mutants.sh: build the grader first (scripts/build.sh)" >&2; exit 2; }

# results.json -> "score max failed-case-names"
summarise() {
  python3 - "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
tests = r["tests"]
failed = [t["name"].split(": ", 1)[1] for t in tests if t["status"] != "passed"]
print(f'{r["score"]:.2f} {sum(t["max_score"] for t in tests):g} {len(tests)} {",".join(failed) or "-"}')
PY
}

build() {  # build DIR SOURCE [cmake args...]: configure, then build the pathtracer only
  local dir=$1 src=$2
  shift 2
  cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF "$@" > "$dir.configure.log" 2>&1 &&
    cmake --build "$dir" -j "$jobs" --target pathtracer > "$dir.build.log" 2>&1
}

rows=()
status=0
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$SECONDS

# The reference build, every case.
echo "== reference"
set +e
"$grader" run -q -j "$jobs" -o "$build_root/reference.grade" > "$build_root/reference.grade.log" 2>&1
set -e
read -r score max n failed < <(summarise "$build_root/reference.grade/results.json")
ref_row="| reference build | all | $score / $max | ${failed} |"
[ "$failed" = "-" ] || status=1
echo "   $score / $max, failed: $failed"

# The starter kit (every function a stub), every case.
echo "== starter kit"
rm -rf "$build_root/kit"
python3 tools/make_starter_kit.py "$build_root/kit" > /dev/null
if build "$build_root/kit.build" "$build_root/kit"; then
  set +e
  "$grader" run -q -j "$jobs" --pathtracer "$build_root/kit.build/bin/pathtracer" -o "$build_root/kit.grade" \
    > "$build_root/kit.grade.log" 2>&1
  set -e
  read -r score max n failed < <(summarise "$build_root/kit.grade/results.json")
  pct=$(python3 -c "print(f'{100*$score/$max:.1f}')")
  kit_row="| starter kit (all stubs) | all | $score / $max ($pct %) | $(echo "$failed" | tr ',' '\n' | wc -l) of $n cases fail |"
  python3 -c "import sys; sys.exit(0 if $score <= 0.10 * $max else 1)" || status=1
else
  kit_row="| starter kit (all stubs) | all | build failed (see $build_root/kit.build.build.log) | |"
  status=1
fi
echo "   $kit_row"

# One build per mutant, graded on its own part's cases.
while read -r name part description; do
  case "$name" in ''|\#*) continue ;; esac
  if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " =~ " $name " ]]; then continue; fi
  echo "== $name (part $part)"
  dir="$build_root/$name"
  if ! build "$dir" "$root" -DPT_MUTANT="$name"; then
    rows+=("| $name | $part | build failed | | no |")
    status=1
    continue
  fi
  set +e
  "$grader" run -q -j "$jobs" --part "$part" --pathtracer "$dir/bin/pathtracer" -o "$dir.grade" > "$dir.grade.log" 2>&1
  set -e
  read -r score max n failed < <(summarise "$dir.grade/results.json")
  if [ "$failed" = "-" ]; then caught=no; status=1; else caught=yes; fi
  nfailed=$([ "$failed" = "-" ] && echo 0 || echo "$failed" | tr ',' '\n' | wc -l)
  rows+=("| $name | $part | $score / $max | $nfailed of $n: ${failed//,/, } | $caught |")
  echo "   caught: $caught ($nfailed of $n cases fail)"
done < grader/mutants.txt

mkdir -p "$(dirname "$table")"
{
  echo "# Mutants: does the grader catch each classic bug?"
  echo
  echo "Each mutant is the reference renderer with one bug planted (\`cmake -DPT_MUTANT=<name>\`, list and"
  echo "descriptions in [grader/mutants.txt](../mutants.txt)), graded on the cases of its part. It is caught"
  echo "when at least one of those cases fails. The reference build and the starter kit are graded on every case."
  echo
  echo "Made by \`grader/grade_mutants.sh\` at commit $(git rev-parse --short HEAD) on $started ($(( (SECONDS - t0) / 60 )) min)."
  echo
  echo "| build | part | score | failing cases |"
  echo "|---|---:|---:|---|"
  echo "$ref_row"
  echo "$kit_row"
  echo
  echo "| mutant | part | score on its part | failing cases | caught |"
  echo "|---|---:|---:|---|---|"
  printf '%s\n' "${rows[@]}"
} > "$table.tmp"
mv "$table.tmp" "$table"
cat "$table"
exit $status
