#!/usr/bin/env bash
# Tests the Gradescope package end to end, without root and without
# /autograder, in steps that share one zip and one AUTOGRADER_ROOT in WORK
# (ctest runs each step as a test of its own, CMakeLists.txt here):
#   zip         make_autograder.sh builds the zip; it is unpacked into
#               WORK/autograder/source (setup.sh and run_autograder must be
#               at its root)
#   contents    setup.sh and run_autograder are executable; the zip holds the
#               case list, the scenes and the grader's sources, sandbox.sh and
#               submission_tools.py; its stages/ are the starter kit's (no
#               solution regions) and it has no hidden case in project/
#   setup       its setup.sh (AUTOGRADER_SKIP_APT=1) builds the grader and
#               checks the references (when the zip has them all)
#   reference   run_autograder grades the reference tree's stages/ on two
#               fast cases: results.json parses and scores full marks
#   broken      run_autograder grades a submission whose sphere.cpp does not
#               compile: results.json scores 0 and shows the compiler's error
#   empty       a submission without stages/ also gets a results.json scoring 0
#
#   instructors/gradescope/test_package.sh [--step STEP --work WORK] [--pathtracer P --grader G]
#
# Without --step, every step in this order, in a temporary WORK (KEEP_TMP=1
# keeps it). The cases' references come from reference_images/ when they are
# there; otherwise P and G (a reference build) make temporary ones with
# `grader make-references --runs 2` (zip step). The timeouts it gives are
# multiplied by PT_TEST_TIMEOUT_SCALE (tests/timeout_scale/timeout_scale.sh).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
. "$root/tests/timeout_scale/timeout_scale.sh"
cases=(p1_empty p3_point_light)
steps=(zip contents setup reference broken empty)

usage() { echo "usage: $0 [--step STEP --work WORK] [--pathtracer P --grader G]" >&2; exit 2; }
ref_pathtracer="" ref_grader="" work="" one_step=""
while [ $# -gt 0 ]; do
  case "$1" in
    --step) one_step=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --pathtracer) ref_pathtracer=$2; shift 2 ;;
    --grader) ref_grader=$2; shift 2 ;;
    *) usage ;;
  esac
done
if [ -n "$one_step" ]; then
  [ -n "$work" ] || usage
  steps=("$one_step")
elif [ -z "$work" ]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/gradescope-test.XXXXXX")
  if [ "${KEEP_TMP:-0}" = 1 ]; then
    echo "test_package: keeping $work"
  else
    trap 'rm -rf "$work"' EXIT
  fi
fi
mkdir -p "$work"
work=$(cd "$work" && pwd)
ag=$work/autograder

failures=0
. "$root/tests/shell/check.sh"  # check DESCRIPTION COMMAND...
case_args=()
for c in "${cases[@]}"; do case_args+=(--case "$c"); done
need() { [ -e "$1" ] || { echo "FAILED: no $1: run the $2 step first" >&2; exit 1; }; }

# ---- 1. The zip, unpacked as Gradescope does ----
step_zip() {
  rm -rf "$ag" "$work/autograder.zip" "$work/references" "$work/reference_work" "$work/submissions" "$work/results"
  # References for the cases.
  local references=$root/reference_images c
  for c in "${cases[@]}"; do
    if [ ! -f "$references/$c/meta.json" ]; then
      if [ -z "$ref_pathtracer" ] || [ -z "$ref_grader" ]; then
        echo "test_package: no reference for $c in reference_images/: pass --pathtracer and --grader of a reference build" >&2
        exit 2
      fi
      references=$work/references
      "$ref_grader" make-references --pathtracer "$ref_pathtracer" --runs 2 "${case_args[@]}" \
        --cases "$root/grader/cases.txt" --scenes "$root/scenes" \
        --references "$references" --work "$work/reference_work" -j 2 --timeout-scale "$(timeout_scale)"
      break
    fi
  done
  echo "$references" >"$work/references"
  echo "test_package: references from $references"
  local zip=$work/autograder.zip
  ALLOW_MISSING_REFERENCES=1 "$here/make_autograder.sh" "$zip"
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
  echo "ok: the zip is made and unpacked in $ag/source"
}

step_contents() {
  need "$ag/source" zip
  check "setup.sh and run_autograder are executable at the zip's root" \
    test -x "$ag/source/setup.sh" -a -x "$ag/source/run_autograder"
  check "the zip holds the case list, the scenes and the grader's sources" \
    test -f "$ag/source/project/grader/cases.txt" -a -f "$ag/source/project/scenes/CBempty.dae" \
    -a -f "$ag/source/project/grader/src/main.cpp"
  local leaked
  if grep -rq --include='*.cpp' --include='*.h' "BEGIN SOLUTION" "$ag/source/project/stages"; then leaked=1; else leaked=0; fi
  check "the zip's stages/ are the starter kit's (no solution regions)" test "$leaked" = 0
  check "the sandbox's script and the intake tool are at the zip's root" \
    test -f "$ag/source/sandbox.sh" -a -x "$ag/source/submission_tools.py"
  # Hidden cases (instructors/hidden_cases/) are in hidden/, never in the kit.
  local names=() n
  [ -f "$ag/source/hidden/cases.txt" ] && mapfile -t names < <(grep -Ev '^[[:space:]]*(#|$)' "$ag/source/hidden/cases.txt" | awk '{ print $1 }')
  for n in ${names[@]+"${names[@]}"}; do
    check "hidden case $n is not named in the kit (project/)" bash -c '! grep -rqw -- "$1" "$2"' _ "$n" "$ag/source/project"
  done
}

# ---- 2. setup.sh, as Gradescope runs it ----
step_setup() {
  need "$ag/source/setup.sh" zip
  (cd "$ag/source" && AUTOGRADER_ROOT=$ag AUTOGRADER_SKIP_APT=1 bash ./setup.sh) >"$work/setup.log" 2>&1 || {
    tail -40 "$work/setup.log"
    echo "FAILED: setup.sh"
    exit 1
  }
  cp "$ag/source/run_autograder" "$ag/run_autograder"
  echo "ok: setup.sh built the grader"
}

# run_graded NAME: runs run_autograder on $work/submissions/NAME; results in
# $work/NAME.json, its output in $work/NAME.log.
run_graded() {
  local name=$1 rc=0 results=$work/results/$1
  need "$ag/pt/bin/grader" setup
  rm -rf "$results"
  (cd "$ag" && AUTOGRADER_ROOT=$ag AUTOGRADER_SUBMISSION=$work/submissions/$name AUTOGRADER_RESULTS=$results \
    GRADER_REFERENCES=$(cat "$work/references") GRADER_JOBS=2 BUILD_TIMEOUT=$(scaled_seconds 1200) \
    GRADER_ARGS="${case_args[*]} --timeout-scale $(timeout_scale)" ./run_autograder) >"$work/$name.log" 2>&1 || rc=$?
  rm -f "$work/$name.json"
  cp "$results/results.json" "$work/$name.json" 2>/dev/null || true
  check "$name: run_autograder exits 0" test "$rc" = 0
  check "$name: results.json written" test -s "$work/$name.json"
}

# ---- 3. The reference's stages/, as a whole starter-kit folder ----
step_reference() {
  local sub=$work/submissions/reference
  rm -rf "$sub"
  mkdir -p "$sub/pathtracer-kit"
  cp -R "$root/stages" "$sub/pathtracer-kit/stages"
  cp "$root/CMakeLists.txt" "$sub/pathtracer-kit/"
  run_graded reference
  check "reference: full marks on ${cases[*]}" python3 - "$work/reference.json" "${#cases[@]}" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
tests = d.get("tests", [])
full = sum(t["max_score"] for t in tests)
print(f"  score {d['score']} of {full} in {len(tests)} tests")
sys.exit(0 if len(tests) == int(sys.argv[2]) and full > 0 and abs(d["score"] - full) < 1e-9 else 1)
EOF
}

# ---- 4. A submission that does not compile ----
step_broken() {
  local sub=$work/submissions/broken
  rm -rf "$sub"
  mkdir -p "$sub"
  cp -R "$root/stages" "$sub/stages"
  printf '\nthis is not C++ %s\n' '@' >>"$sub/stages/part1_raytracing/sphere.cpp"
  run_graded broken
  check "broken: score 0, the compiler's error on sphere.cpp in the output" python3 - "$work/broken.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
out = d.get("output", "")
print("  score", d["score"], "| output:", " / ".join(out.splitlines()[:3])[:300])
sys.exit(0 if d["score"] == 0 and "sphere.cpp" in out and "error" in out else 1)
EOF
}

# ---- 5. A submission without stages/ ----
step_empty() {
  local sub=$work/submissions/empty
  rm -rf "$sub"
  mkdir -p "$sub"
  echo "int main() {}" >"$sub/main.cpp"
  run_graded empty
  check "no stages/: score 0 and says so" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
sys.exit(0 if d["score"] == 0 and "stages/" in d["output"] else 1)' "$work/empty.json"
}

for step in "${steps[@]}"; do
  case "$step" in
    zip | contents | setup | reference | broken | empty) "step_$step" ;;
    *) echo "test_package: no step '$step'" >&2; exit 2 ;;
  esac
done

if [ "$failures" -ne 0 ]; then
  for log in reference broken empty; do
    [ -f "$work/$log.log" ] && { echo "---- end of run_autograder's output, $log submission:"; tail -30 "$work/$log.log"; }
  done
  echo "test_package: $failures checks failed (logs in $work)"
  exit 1
fi
echo "test_package: all checks passed"
