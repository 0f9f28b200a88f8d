#!/usr/bin/env bash
# Grades a folder of submissions, one student per subfolder (each a
# student's starter-kit folder), the way the Gradescope autograder does.
#
#   instructors/batch/grade_folder.sh SUBMISSIONS_DIR OUT_DIR [-j N] [--student NAME]...
#                                [--prepare-only] [--no-summary] [--summary-only]
#
#   -j N             grade N submissions at a time (default 1); each gets
#                    GRADER_JOBS build jobs and cases at a time (default: CPUs / N)
#   --student NAME   only this subfolder of SUBMISSIONS_DIR (repeatable)
#   --prepare-only   only make OUT_DIR/.autograder (the grader), then stop
#   --no-summary     do not write scores.csv (for one job of many)
#   --summary-only   only write scores.csv from what is graded
#
# Once per OUT_DIR it unpacks the autograder into OUT_DIR/.autograder
# (instructors/gradescope/make_autograder.sh --unpacked) and builds the grader
# there (its setup.sh, without apt). Delete that folder to start afresh.
# Then, for each student S, instructors/gradescope/run_autograder builds S's
# sources (the .cpp and .h files of its part folders) with the starter kit in
# its own build folder, sandboxed as Gradescope does, and grades it (as
# root, one student at a time: the sandbox's accounts are shared, so -j N
# waits its turn; OUT_DIR must then be reachable by other users, o+x):
#   OUT_DIR/S/results.json    Gradescope's results (always written)
#   OUT_DIR/S/report.html, report.txt, build_log.txt, grader_log.txt, autograder_log.txt
# and OUT_DIR/scores.csv has one row per student: student,score,max,failed
# (failed: the cases that did not get full marks, or why nothing was graded).
#
# Environment: GRADER_ARGS (more `grader run` arguments, e.g. "--part 1"),
# GRADER_REFERENCES, GRADER_JOBS, BUILD_TIMEOUT are passed to run_autograder;
# ALLOW_MISSING_REFERENCES to make_autograder.sh; KEEP_WORK=1 keeps each
# student's build in OUT_DIR/S/.work.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
die() { echo "grade_folder: $*" >&2; exit 2; }

positional=()
parallel=1
students=()
prepare_only=0 summary=1 summary_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    -j) [ $# -ge 2 ] || die "-j needs a number"; parallel=$2; shift 2 ;;
    -j*) parallel=${1#-j}; shift ;;
    --student) [ $# -ge 2 ] || die "--student needs a name"; students+=("$2"); shift 2 ;;
    --prepare-only) prepare_only=1; shift ;;
    --no-summary) summary=0; shift ;;
    --summary-only) summary_only=1; shift ;;
    -*) usage >&2; exit 2 ;;
    *) positional+=("$1"); shift ;;
  esac
done
[ ${#positional[@]} -eq 2 ] || { usage >&2; exit 2; }
[[ "$parallel" =~ ^[1-9][0-9]*$ ]] || die "-j $parallel: expected a positive number"
submissions=$(cd "${positional[0]}" 2>/dev/null && pwd -P) || die "${positional[0]}: no such folder"
mkdir -p "${positional[1]}"
out=$(cd "${positional[1]}" && pwd)
ag=$out/.autograder

if [ ${#students[@]} -eq 0 ]; then
  while IFS= read -r -d '' d; do students+=("$(basename "$d")"); done \
    < <(find "$submissions" -mindepth 1 -maxdepth 1 -type d -not -name '.*' -print0 | sort -z)
fi
for s in ${students[@]+"${students[@]}"}; do
  [ -d "$submissions/$s" ] || die "$submissions/$s: no such submission folder"
done

# ---- The autograder, once per OUT_DIR ----
prepare() {
  [ -f "$ag/ready" ] && return 0
  exec 9>"$out/.prepare.lock"
  flock 9 2>/dev/null || true
  if [ ! -f "$ag/ready" ]; then
    echo "grade_folder: preparing the autograder in $ag (log: $out/.prepare.log)"
    rm -rf "$ag"
    if ! { "$root/instructors/gradescope/make_autograder.sh" --unpacked "$ag/source" &&
      (cd "$ag/source" && AUTOGRADER_ROOT=$ag AUTOGRADER_SKIP_APT=1 AUTOGRADER_GRADER_ONLY=1 bash ./setup.sh); } >"$out/.prepare.log" 2>&1; then
      tail -30 "$out/.prepare.log" >&2
      die "preparing the autograder failed (log: $out/.prepare.log)"
    fi
    # Each student gets a build folder of their own.
    rm -rf "$ag/pt/build" "$ag/pt/tree"
    touch "$ag/ready"
  fi
  exec 9>&-
}

cpus=$(nproc 2>/dev/null || echo 1)
per_student_jobs=${GRADER_JOBS:-$((cpus / parallel > 0 ? cpus / parallel : 1))}

# grade_one NAME: grades one submission into $out/NAME.
grade_one() {
  local s=$1 dest=$out/$1 rc=0
  local work=$dest/.work
  rm -rf "$dest"
  mkdir -p "$work"
  AUTOGRADER_ROOT=$work AUTOGRADER_SOURCE=$ag/source AUTOGRADER_PT=$ag/pt AUTOGRADER_SUBMISSION=$submissions/$s \
    AUTOGRADER_RESULTS=$work/results GRADER_BIN=$ag/pt/bin/grader GRADER_JOBS=$per_student_jobs \
    bash "$ag/source/run_autograder" >"$dest/autograder_log.txt" 2>&1 || rc=$?
  local f
  for f in results.json build_log.txt grader_log.txt grader_out/report.html grader_out/report.txt; do
    [ -f "$work/results/$f" ] && cp "$work/results/$f" "$dest/"
  done
  [ "${KEEP_WORK:-0}" = 1 ] || rm -rf "$work"
  local line
  line=$(python3 - "$dest/results.json" <<'EOF' 2>/dev/null || echo "no results.json"
import json, sys
d = json.load(open(sys.argv[1]))
# Tests with points: the public cases and each part's hidden total (the
# staff's per-hidden-case tests carry none).
tests = [t for t in d.get("tests", []) if "max_score" in t]
if tests:
    print(f"{d['score']:g} / {sum(t['max_score'] for t in tests):g}")
else:
    first = (d.get("output") or "nothing graded").strip().splitlines()[0]
    print(f"{d['score']:g}, not graded: {first.split('. ')[0].rstrip('.:')}")
EOF
  )
  echo "grade_folder: $s: $line$([ "$rc" = 0 ] || echo " (run_autograder exit status $rc)")"
}

write_summary() {
  python3 - "$out" "$ag/source/project/grader/cases.txt" "${students[@]}" <<'EOF'
import csv, json, os, sys
out, cases_file, students = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = []
for s in students:
    try:
        d = json.load(open(os.path.join(out, s, "results.json")))
    except (OSError, ValueError):
        rows.append([s, "", "", "not graded"])
        continue
    tests = [t for t in d.get("tests", []) if "max_score" in t]  # the staff's hidden-case tests carry no points
    if tests:
        full = sum(t["max_score"] for t in tests)
        failed = [t["name"].split(": ", 1)[-1] for t in tests if t["score"] < t["max_score"]]
        rows.append([s, d["score"], full, " ".join(failed)])
    else:
        first = (d.get("output") or "nothing graded").strip().splitlines()[0]
        rows.append([s, d["score"], None, "not graded: " + first.split(". ")[0].rstrip(".:")])
# A submission with no graded case is out of what the others were graded on
# (or, when none was graded, of the whole case list).
graded = [r[2] for r in rows if isinstance(r[2], (int, float))]
if graded:
    full = max(graded)
else:
    full = 0
    try:
        for line in open(cases_file):
            f = line.split()
            if f and not f[0].startswith("#"):
                full += float(f[3])
    except OSError:
        full = ""
for r in rows:
    if r[2] is None:
        r[2] = full
def num(x):
    return f"{x:g}" if isinstance(x, (int, float)) else x
with open(os.path.join(out, "scores.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["student", "score", "max", "failed"])
    for r in rows:
        w.writerow([r[0], num(r[1]), num(r[2]), r[3]])
scores = [r[1] for r in rows if isinstance(r[1], (int, float))]
mean = sum(scores) / len(scores) if scores else 0
print(f"grade_folder: {len(rows)} students, {len(scores)} with results, mean score {mean:.2f}: {os.path.join(out, 'scores.csv')}")
EOF
}

if [ "$summary_only" = 1 ]; then
  write_summary
  exit 0
fi
prepare
[ "$prepare_only" = 1 ] && { echo "grade_folder: autograder ready in $ag"; exit 0; }
[ ${#students[@]} -gt 0 ] || die "$submissions: no submission folders"

echo "grade_folder: ${#students[@]} submissions, $parallel at a time, $per_student_jobs jobs each"
running=0
for s in "${students[@]}"; do
  if [ "$running" -ge "$parallel" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  grade_one "$s" &
  running=$((running + 1))
done
wait
[ "$summary" = 1 ] && write_summary
exit 0
