#!/usr/bin/env bash
# The grader's fairness check, the mutants' twin. Each legal variant of
# instructors/legal_variants/variants.txt is a correct solution that differs
# from the reference the way real students' code does (another roulette
# probability, recursion, a binary BVH, ...), kept as a patch,
# instructors/legal_variants/patches/<name>.patch, against the reference
# tree. This script builds each variant's pathtracer in a copy of the tree
# (instructors/patch_catalogue.sh, shared with the mutants), grades it and
# the reference build on every case at each seed of --seeds, and writes
# the table to instructors/legal_variants/variants.md. With --hidden, the
# hidden cases (instructors/hidden_cases/) are graded too, each counted as
# a case of its own, and the table goes to variants_hidden.md. Each
# --grader-arg is passed to every `grader run` (e.g. --grader-arg --sandbox
# --grader-arg bwrap --grader-arg --sandbox-user --grader-arg A,B: the
# renders in the Gradescope package's sandbox).
#
#   instructors/legal_variants/grade_variants.sh [--seeds 1,2,3,4,5] [--build-root DIR] [--table FILE] [-j N] [--only NAME]...
#                                                [--hidden] [--grader-arg ARG]...
#   instructors/legal_variants/grade_variants.sh --check              # every patch listed, and applies to this tree
#   instructors/legal_variants/grade_variants.sh --plant NAME DIR     # a copy of the tree with one variant, in DIR
#
# Slow (one incremental build per variant, one grading run per variant and
# seed: about an hour for 16 variants at 5 seeds on 2 cores): run it on
# purpose, not in the test suite. Exit status: 0 when the reference and
# every variant score full marks at every seed; 1 otherwise; 2 for bad
# usage or a patch that does not apply.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
tool=grade_variants.sh
noun=variant
list=instructors/legal_variants/variants.txt
patches=instructors/legal_variants/patches
build_root="$root/build/legal_variants"
table="$root/instructors/legal_variants/variants.md"
jobs=$(nproc 2>/dev/null || echo 2)
seeds=1,2,3,4,5
only=()
mode=grade
plant_name="" plant_dir=""
. instructors/patch_catalogue.sh
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds)
      [ $# -ge 2 ] || { echo "$tool: --seeds needs a value" >&2; exit 2; }
      [[ "$2" =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "$tool: --seeds $2: want seeds separated by commas (1,2,3)" >&2; exit 2; }
      seeds=$2; shift 2 ;;
    --hidden) grade_extra+=(--hidden-cases "$root/instructors/hidden_cases/cases.txt")
              [ "$table" = "$root/instructors/legal_variants/variants.md" ] && table="$root/instructors/legal_variants/variants_hidden.md"
              shift ;;
    --grader-arg) [ $# -ge 2 ] || { echo "$tool: --grader-arg needs a value" >&2; exit 2; }
                  grade_extra+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) catalogue_option "$@" || exit 2; shift "$catalogue_shift" ;;
  esac
done
catalogue_start
IFS=, read -r -a seed_list <<< "$seeds"

started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$SECONDS
# The commit graded: the tree is copied now, and HEAD may move during the run.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

# The reference build at every seed: the control (a case it fails at some
# seed is the grader's chance failure, not a variant's).
for s in "${seed_list[@]}"; do
  echo "== grade reference, seed $s"
  grade "$root/build/bin/pathtracer" "$build_root/reference.s$s.grade" --seed "$s"
done

# Every variant built (names, part_of, description_of, built), then graded
# at every seed.
catalogue_build_all
for name in "${names[@]}"; do
  [ -n "${built[$name]:-}" ] || { echo "== $name: build failed ($build_root/$name.build.log)"; continue; }
  for s in "${seed_list[@]}"; do
    echo "== grade $name (part ${part_of[$name]}), seed $s"
    grade "$build_root/bin/$name" "$build_root/$name.s$s.grade" --seed "$s"
  done
done

# The table, from every results.json.
for name in "${names[@]}"; do
  printf '%s\t%s\t%s\t%s\n' "$name" "${part_of[$name]}" "${built[$name]:-0}" "${description_of[$name]}"
done > "$build_root/entries.tsv"
mkdir -p "$(dirname "$table")"
set +e
python3 - "$build_root" "$seeds" "$commit" "$started" "$(( (SECONDS - t0) / 60 ))" "$table.tmp" <<'PY'
import json, os, sys
build_root, seeds, commit, started, minutes, out = sys.argv[1:7]
seeds = seeds.split(",")
entries = [line.split("\t", 3) for line in open(os.path.join(build_root, "entries.tsv")).read().splitlines() if line]

def load(stem, seed):
    path = os.path.join(build_root, f"{stem}.s{seed}.grade", "results.json")
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None

def short(text):
    # The verdict line and the statistics line of a case's output.
    lines = [l for l in text.splitlines() if l and not l.startswith("Command:")]
    return " / ".join(lines[:2])[:300].replace("|", "/")

def per_case(r):
    """One entry per graded case: the public cases' tests, and the hidden
    cases' staff tests (their per-part totals left out)."""
    out = []
    for t in r["tests"]:
        extra = t.get("extra_data", {})
        if "case" in extra:
            out.append({"name": extra["case"], "score": extra["score"], "max_score": extra["max_score"],
                        "output": t.get("output", "")})
    return out

def row(stem):
    """Scores per seed, {case: [seeds]}, {case: first reason}, full marks at every seed."""
    scores, lost, why, full, mx = [], {}, {}, True, 0
    for s in seeds:
        r = load(stem, s)
        if r is None:
            scores.append("no results")
            full = False
            continue
        tests = per_case(r)
        mx = sum(t["max_score"] for t in tests)
        scores.append(f'{r["score"]:.2f}')
        for t in tests:
            if t["score"] < t["max_score"]:
                case = t["name"]
                lost.setdefault(case, []).append(s)
                why.setdefault(case, f"seed {s}: " + short(t.get("output", "")))
                full = False
    return scores, lost, why, full, mx

def cases_cell(lost):
    if not lost:
        return "-"
    return ", ".join(f"{c} ({','.join(ss)})" for c, ss in lost.items())

lines = []
ok_count = 0
ref_scores, ref_lost, ref_why, ref_full, mx = row("reference")
rows, details = [], []
for name, part, built, description in entries:
    if built != "1":
        rows.append(f"| {name} | {part} | " + " | ".join("build failed" for _ in seeds) + " | | no |")
        continue
    scores, lost, why, full, m = row(name)
    mx = mx or m
    ok_count += full
    rows.append(f"| {name} | {part} | " + " | ".join(scores) + f" | {len(lost)}: {cases_cell(lost)} | {'yes' if full else 'no'} |")
    if why:
        details.append(f"- **{name}**: " + "; ".join(f"{c}: {w}" for c, w in why.items()))

seed_cols = " | ".join(f"seed {s}" for s in seeds)
out_lines = [
    "# Legal variants: does the grader pass correct code that differs from the reference?",
    "",
    "Each legal variant is the reference renderer with one correct difference that real students'",
    "code has: the patch [patches/<name>.patch](patches/) applied to a copy of the tree (list, parts",
    "and descriptions in [variants.txt](variants.txt)). Each is graded on every case at each seed",
    "(`grader run --seed S`), and so is the reference build, as the control. A correct build should",
    "score full marks at every seed; \"cases that lose points\" lists each case that lost points at",
    "some seed, with the seeds in brackets. Why each case lost points (the grader's verdict and",
    "statistics at the first seed it did) is listed under the table.",
    "",
    f"Made by `instructors/legal_variants/grade_variants.sh --seeds {','.join(seeds)}` at commit {commit} on {started} ({minutes} min): "
    f"{ok_count} of {len(entries)} variants have full marks at every seed.",
    "",
    f"| build | part | {seed_cols} | cases that lose points (seeds) | full marks at every seed |",
    "|---|---:|" + "---:|" * len(seeds) + "---|---|",
    f"| reference build | - | " + " | ".join(ref_scores) + f" | {len(ref_lost)}: {cases_cell(ref_lost)} | {'yes' if ref_full else 'no'} |",
] + rows + ["", f"Scores are out of {mx:g}.", ""]
if ref_why or details:
    out_lines += ["## Why the cases lost points", ""]
    if ref_why:
        out_lines.append("- **reference build**: " + "; ".join(f"{c}: {w}" for c, w in ref_why.items()))
    out_lines += details
    out_lines.append("")
open(out, "w").write("\n".join(out_lines))
sys.exit(0 if ok_count == len(entries) and ref_full else 1)
PY
status=$?
set -e
[ $status -le 1 ] || { echo "$tool: could not write the table" >&2; exit 2; }
mv "$table.tmp" "$table"
cat "$table"
exit $status
