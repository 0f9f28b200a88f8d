#!/usr/bin/env bash
# The grader's self-check. Each mutant of instructors/mutants/mutants.txt is one classic
# student bug, kept as a patch, instructors/mutants/patches/<name>.patch, against the
# reference tree (the reference code itself holds no trace of it). This
# script applies each patch to a copy of the tree, builds that copy's
# pathtracer, grades it on every case, grades the reference build and the
# starter kit too, and writes the table to instructors/mutants/mutants.md.
#
#   instructors/mutants/grade_mutants.sh [--build-root DIR] [--table FILE] [-j N] [--only NAME]...
#   instructors/mutants/grade_mutants.sh --check              # every patch listed, and applies to this tree
#   instructors/mutants/grade_mutants.sh --plant NAME DIR     # a copy of the tree with one bug planted, in DIR
#
# A mutant is caught when it loses points on some case; the table also says
# whether the cases of its own part caught it. Slow (one incremental build
# and one grading run per mutant: about 30 s each on 2 cores): run it on
# purpose, not in the test suite. Exit status: 0 when the reference passes
# everything, the starter kit scores at most 10 % and every mutant is
# caught; 1 otherwise; 2 for bad usage or a patch that does not apply.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
tool=grade_mutants.sh
noun=mutant
list=instructors/mutants/mutants.txt
patches=instructors/mutants/patches
build_root="$root/build/mutants"
table="$root/instructors/mutants/mutants.md"
jobs=$(nproc 2>/dev/null || echo 2)
only=()
mode=grade
plant_name="" plant_dir=""
# Copying, checking, planting, building and summarising are shared with
# the legal variants (instructors/patch_catalogue.sh).
. instructors/patch_catalogue.sh
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) catalogue_option "$@" || exit 2; shift "$catalogue_shift" ;;
  esac
done
catalogue_start

status=0
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$SECONDS
# The commit graded: the tree is copied now, and HEAD may move during the run.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

# The reference build, every case.
echo "== reference"
grade "$root/build/bin/pathtracer" "$build_root/reference.grade"
read -r score max n failed < <(summarise "$build_root/reference.grade/results.json")
ref_row="| reference build | $score / $max | ${failed//,/, } |"
[ "$failed" = "-" ] || status=1
echo "   $score / $max, points lost on: $failed"

# The starter kit (every function a stub), every case.
echo "== starter kit"
rm -rf "$build_root/kit" "$build_root/kit.build"
python3 instructors/starter_kit/make_starter_kit.py "$build_root/kit" > /dev/null
mkdir -p "$build_root/kit.build"
if build_pathtracer "$build_root/kit.build" "$build_root/kit"; then
  grade "$build_root/kit.build/bin/pathtracer" "$build_root/kit.grade"
  read -r score max n failed < <(summarise "$build_root/kit.grade/results.json")
  pct=$(python3 -c "print(f'{100*$score/max($max, 1):.1f}')")
  kit_row="| starter kit (all stubs) | $score / $max ($pct %) | $(echo "$failed" | tr ',' '\n' | grep -vc '^-$') of $n cases lose points |"
  python3 -c "import sys; sys.exit(0 if $max > 0 and $score <= 0.10 * $max else 1)" || status=1
else
  kit_row="| starter kit (all stubs) | build failed (see $build_root/kit.build.build.log) | |"
  status=1
fi
echo "   $kit_row"

# Every mutant built (names, part_of, description_of, built).
catalogue_build_all

rows=()
caught_count=0
for name in "${names[@]}"; do
  part=${part_of[$name]}
  if [ -z "${built[$name]:-}" ]; then
    rows+=("| $name | $part | build failed ($build_root/$name.build.log) | | | no |")
    status=1
    continue
  fi
  echo "== grade $name (part $part)"
  grade_from_part "$build_root/bin/$name" "$build_root/$name.grade" \
    "$(first_part_of_patch "$patches/$name.patch")" "$build_root/reference.grade"
  read -r score max n failed < <(summarise "$build_root/$name.grade/results.json")
  if [ "$failed" = "-" ]; then
    caught=no; status=1; nfailed=0; by=""
  else
    caught=yes; caught_count=$((caught_count + 1))
    nfailed=$(echo "$failed" | tr ',' '\n' | wc -l)
    by=$(parts_of "$failed")
  fi
  own=$([[ " $by " == *" $part "* ]] && echo yes || echo no)
  rows+=("| $name | $part | $score / $max | $nfailed: ${failed//,/, } | ${by:--} | $caught$([ "$caught" = yes ] && [ "$own" = no ] && echo ' (not by its part)' || true) |")
  echo "   caught: $caught ($nfailed cases lose points; parts: ${by:--})"
done

mkdir -p "$(dirname "$table")"
{
  echo "# Mutants: does the grader catch each classic bug?"
  echo
  echo "Each mutant is the reference renderer with one classic student bug planted: the patch"
  echo "[patches/<name>.patch](patches/) applied to a copy of the tree (list, parts and descriptions"
  echo "in [mutants.txt](mutants.txt)). Every build is graded on every case (a mutant whose patch touches only"
  echo "the stage of part N and later is rendered on the cases of parts N and later: the earlier parts run none of"
  echo "its code, and their results are the reference build's); a mutant is caught"
  echo "when it loses points on some case. \"parts\" lists the parts whose cases took points; \"part\" is the"
  echo "part the bug belongs to. The reference build and the starter kit are graded on every case too."
  echo
  echo "Made by \`instructors/mutants/grade_mutants.sh\` at commit $commit on $started ($(( (SECONDS - t0) / 60 )) min): $caught_count of ${#names[@]} mutants caught."
  echo
  echo "| build | score | cases that lose points |"
  echo "|---|---:|---|"
  echo "$ref_row"
  echo "$kit_row"
  echo
  echo "| mutant | part | score | cases that lose points | parts | caught |"
  echo "|---|---:|---:|---|---|---|"
  printf '%s\n' "${rows[@]}"
} > "$table.tmp"
mv "$table.tmp" "$table"
cat "$table"
exit $status
