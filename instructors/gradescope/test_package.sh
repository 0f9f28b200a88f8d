#!/usr/bin/env bash
# Tests the Gradescope package end to end, without root and without
# /autograder:
#   1. make_autograder.sh builds the zip; setup.sh and run_autograder are at
#      its root and executable;
#   2. its setup.sh (AUTOGRADER_SKIP_APT=1) builds the grader in a temporary
#      AUTOGRADER_ROOT and checks the references (when the zip has them all);
#   3. run_autograder grades the reference tree's stages/ on two fast cases:
#      results.json parses and scores full marks;
#   4. run_autograder grades a submission whose sphere.cpp does not compile:
#      results.json scores 0 and shows the compiler's error;
#   5. a submission without stages/ also gets a results.json scoring 0.
#
#   instructors/gradescope/test_package.sh [--pathtracer P --grader G]
#
# The cases' references come from reference_images/ when they are there;
# otherwise P and G (a reference build) make temporary ones with
# `grader make-references --runs 2`. KEEP_TMP=1 keeps the temporary folder.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cases=(p1_empty p3_point_light)

ref_pathtracer="" ref_grader=""
while [ $# -gt 0 ]; do
  case "$1" in
    --pathtracer) ref_pathtracer=$2; shift 2 ;;
    --grader) ref_grader=$2; shift 2 ;;
    *) echo "usage: $0 [--pathtracer P --grader G]" >&2; exit 2 ;;
  esac
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/gradescope-test.XXXXXX")
if [ "${KEEP_TMP:-0}" = 1 ]; then
  echo "test_package: keeping $tmp"
else
  trap 'rm -rf "$tmp"' EXIT
fi

failures=0
check() {  # check DESCRIPTION COMMAND...
  local what=$1
  shift
  if "$@"; then
    echo "ok: $what"
  else
    echo "FAILED: $what"
    failures=$((failures + 1))
  fi
}

# ---- References for the cases ----
case_args=()
for c in "${cases[@]}"; do case_args+=(--case "$c"); done
references=$root/reference_images
for c in "${cases[@]}"; do
  if [ ! -f "$references/$c/meta.json" ]; then
    if [ -z "$ref_pathtracer" ] || [ -z "$ref_grader" ]; then
      echo "test_package: no reference for $c in reference_images/: pass --pathtracer and --grader of a reference build" >&2
      exit 2
    fi
    references=$tmp/references
    "$ref_grader" make-references --pathtracer "$ref_pathtracer" --runs 2 "${case_args[@]}" \
      --cases "$root/grader/cases.txt" --scenes "$root/scenes" \
      --references "$references" --work "$tmp/reference_work" -j 2
    break
  fi
done
echo "test_package: references from $references"

# ---- 1. The zip ----
zip=$tmp/autograder.zip
ALLOW_MISSING_REFERENCES=1 "$here/make_autograder.sh" "$zip"
ag=$tmp/autograder
mkdir -p "$ag/source"
python3 - "$zip" "$ag/source" <<'EOF'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as z:
    names = z.namelist()
    assert "setup.sh" in names and "run_autograder" in names, "setup.sh and run_autograder must be at the zip's root"
    for info in z.infolist():
        path = z.extract(info, sys.argv[2])
        mode = info.external_attr >> 16
        if mode:
            os.chmod(path, mode & 0o7777)
EOF
check "setup.sh and run_autograder are executable at the zip's root" \
  test -x "$ag/source/setup.sh" -a -x "$ag/source/run_autograder"
check "the zip holds the case list, the scenes and the grader's sources" \
  test -f "$ag/source/project/grader/cases.txt" -a -f "$ag/source/project/scenes/CBempty.dae" \
  -a -f "$ag/source/project/grader/src/main.cpp"
if grep -rq --include='*.cpp' --include='*.h' "BEGIN SOLUTION" "$ag/source/project/stages"; then leaked=1; else leaked=0; fi
check "the zip's stages/ are the starter kit's (no solution regions)" test "$leaked" = 0

# ---- 2. setup.sh, as Gradescope runs it ----
(cd "$ag/source" && AUTOGRADER_ROOT=$ag AUTOGRADER_SKIP_APT=1 bash ./setup.sh) >"$tmp/setup.log" 2>&1 || {
  tail -40 "$tmp/setup.log"
  echo "FAILED: setup.sh"
  exit 1
}
echo "ok: setup.sh built the grader"
cp "$ag/source/run_autograder" "$ag/run_autograder"

# run_graded NAME: runs run_autograder on $ag/submission; results in $tmp/NAME.json.
run_graded() {
  rm -rf "$ag/results"
  local rc=0
  (cd "$ag" && AUTOGRADER_ROOT=$ag GRADER_REFERENCES=$references GRADER_JOBS=2 \
    GRADER_ARGS="${case_args[*]}" ./run_autograder) >"$tmp/$1.log" 2>&1 || rc=$?
  cp "$ag/results/results.json" "$tmp/$1.json" 2>/dev/null || true
  check "$1: run_autograder exits 0" test "$rc" = 0
  check "$1: results.json written" test -s "$tmp/$1.json"
}

# ---- 3. The reference's stages/, as a whole starter-kit folder ----
rm -rf "$ag/submission"
mkdir -p "$ag/submission/pathtracer-kit"
cp -R "$root/stages" "$ag/submission/pathtracer-kit/stages"
cp "$root/CMakeLists.txt" "$ag/submission/pathtracer-kit/"
run_graded reference
check "reference: full marks on ${cases[*]}" python3 - "$tmp/reference.json" "${#cases[@]}" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
tests = d.get("tests", [])
full = sum(t["max_score"] for t in tests)
print(f"  score {d['score']} of {full} in {len(tests)} tests")
sys.exit(0 if len(tests) == int(sys.argv[2]) and full > 0 and abs(d["score"] - full) < 1e-9 else 1)
EOF

# ---- 4. A submission that does not compile ----
rm -rf "$ag/submission"
mkdir -p "$ag/submission"
cp -R "$root/stages" "$ag/submission/stages"
printf '\nthis is not C++ %s\n' '@' >>"$ag/submission/stages/part1_raytracing/sphere.cpp"
run_graded broken
check "broken: score 0, the compiler's error on sphere.cpp in the output" python3 - "$tmp/broken.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
out = d.get("output", "")
print("  score", d["score"], "| output:", " / ".join(out.splitlines()[:3])[:300])
sys.exit(0 if d["score"] == 0 and "sphere.cpp" in out and "error" in out else 1)
EOF

# ---- 5. A submission without stages/ ----
rm -rf "$ag/submission"
mkdir -p "$ag/submission"
echo "int main() {}" >"$ag/submission/main.cpp"
run_graded empty
check "no stages/: score 0 and says so" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
sys.exit(0 if d["score"] == 0 and "stages/" in d["output"] else 1)' "$tmp/empty.json"

if [ "$failures" -ne 0 ]; then
  for log in reference broken empty; do
    [ -f "$tmp/$log.log" ] && { echo "---- end of run_autograder's output, $log submission:"; tail -30 "$tmp/$log.log"; }
  done
  echo "test_package: $failures checks failed (KEEP_TMP=1 keeps the logs)"
  exit 1
fi
echo "test_package: all checks passed"
