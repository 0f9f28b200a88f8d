#!/usr/bin/env bash
# Measures the grader's hints ("Likely cause" lines) on bugs the catalogue of
# known bugs was not made from. Each bug of held_out.txt is a patch,
# patches/<name>.patch, against the reference tree; this script builds each
# patched pathtracer (as grade_mutants.sh does), grades it on the cases of
# its part and the later ones, as any submission, and then scores the hints
# (score_held_out.py): is the bug's function the first hint, among the
# first three, and is its part. The table goes to held_out.md.
#
#   instructors/mutants/held_out/grade_held_out.sh [--build-root DIR] [--table FILE] [-j N] [--only NAME]...
#   instructors/mutants/held_out/grade_held_out.sh --score-only [--build-root DIR] [--table FILE]
#   instructors/mutants/held_out/grade_held_out.sh --check          # every patch listed, and applies
#
# --score-only scores the folders an earlier run graded, with the grader and
# catalogue of this tree (nothing is rendered): for measuring a change of the
# hints or of the catalogue. These bugs must never go into mutants.txt or
# the catalogue; a bug that joins the catalogue leaves this list.
# Slow (one build and one grading run per bug, about a minute of CPU each).
set -euo pipefail
cd "$(dirname "$0")/../../.."
root=$(pwd)
tool=grade_held_out.sh
noun=bug
list=instructors/mutants/held_out/held_out.txt
patches=instructors/mutants/held_out/patches
build_root="$root/build/held_out"
table="$root/instructors/mutants/held_out/held_out.md"
jobs=$(nproc 2>/dev/null || echo 2)
only=()
mode=grade
score_only=0
plant_name="" plant_dir=""
. instructors/patch_catalogue.sh
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    --score-only) score_only=1; shift ;;
    *) catalogue_option "$@" || exit 2; shift "$catalogue_shift" ;;
  esac
done
# A held-out bug in the catalogue's list would be measured on itself.
while read -r name _; do
  if grep -qE "^$name[[:space:]]" instructors/mutants/mutants.txt; then
    echo "$tool: $name is a mutant of instructors/mutants/mutants.txt too: a held-out bug must stay out of the catalogue" >&2
    exit 2
  fi
done < <(catalogue_lines)
catalogue_start

if [ "$score_only" = 0 ]; then
  t0=$SECONDS
  # Grade with a copy of the grader: the tree's may be rebuilt meanwhile.
  cp "$grader" "$build_root/grader"
  grading_grader="$build_root/grader"
  catalogue_build_all
  for name in "${names[@]}"; do
    [ -n "${built[$name]:-}" ] || { echo "== $name: build failed ($build_root/$name.build.log)"; continue; }
    first=$(first_part_of_patch "$patches/$name.patch")
    args=()
    for p in $(seq "$first" 9); do args+=(--part "$p"); done
    echo "== grade $name (parts $first-9)"
    rm -rf "$build_root/$name.grade"
    grader=$grading_grader grade "$build_root/bin/$name" "$build_root/$name.grade" "${args[@]}"
  done
  echo "graded in $(( (SECONDS - t0) / 60 )) min"
fi
python3 instructors/mutants/held_out/score_held_out.py "$build_root" --grader "$grader" --table "$table"
