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
build_root="$root/build/mutants"
table="$root/instructors/mutants/mutants.md"
jobs=$(nproc 2>/dev/null || echo 2)
only=()
mode=grade
plant_name="" plant_dir=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-root) build_root=$2; shift 2 ;;
    --table) table=$2; shift 2 ;;
    -j) jobs=$2; shift 2 ;;
    --only) only+=("$2"); shift 2 ;;
    --check) mode=check; shift ;;
    --plant) mode=plant; plant_name=${2:-}; plant_dir=${3:-}; shift 3 || { echo "grade_mutants.sh: --plant NAME DIR" >&2; exit 2; } ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "grade_mutants.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done

list=instructors/mutants/mutants.txt
patches=instructors/mutants/patches

# name part description, one per line, from the list.
mutant_lines() { grep -vE '^[[:space:]]*(#|$)' "$list"; }

# Copies the tracked source tree (without the reference images) to $1.
copy_tree() {
  local dest=$1
  rm -rf "$dest"
  mkdir -p "$dest"
  if git -C "$root" rev-parse --git-dir > /dev/null 2>&1; then
    git -C "$root" ls-files -z | grep -zv '^reference_images/' | (cd "$root" && xargs -0 cp --parents -t "$dest")
  else
    (cd "$root" && find . -path ./build -prune -o -path './build-*' -prune -o -path ./reference_images -prune \
       -o -type f -print0 | xargs -0 cp --parents -t "$dest")
  fi
}

# Applies (or with -R reverts) patch $2 inside folder $1.
apply_patch() {
  local dir=$1 patch=$2
  shift 2
  (cd "$dir" && git apply "$@" "$patch")
}

# --check: the list and the folder agree, every patch touches only stages/
# or common/, and applies to this tree.
check() {
  local status=0 name part rest
  declare -A listed=()
  while read -r name part rest; do
    listed[$name]=1
    [[ "$part" =~ ^[1-5]$ ]] || { echo "$list: $name: part '$part' is not 1-5"; status=1; }
    [ -n "$rest" ] || { echo "$list: $name: no description"; status=1; }
    local p="$patches/$name.patch"
    if [ ! -f "$p" ]; then echo "$list: $name: no patch $p"; status=1; continue; fi
    local touched
    touched=$(grep -E '^\+\+\+ ' "$p" | sed -E 's#^\+\+\+ b/##; s#\t.*##')
    [ -n "$touched" ] || { echo "$p: not a patch (no +++ lines)"; status=1; continue; }
    while read -r f; do
      case "$f" in stages/*|common/*) ;; *) echo "$p: changes $f (only stages/ and common/ may change)"; status=1 ;; esac
    done <<< "$touched"
    (cd "$root" && git apply --check "$p" 2> /tmp/grade_mutants.$$.err) \
      || { echo "$p: does not apply: $(head -1 /tmp/grade_mutants.$$.err)"; status=1; }
  done < <(mutant_lines)
  rm -f /tmp/grade_mutants.$$.err
  for p in "$patches"/*.patch; do
    [ -e "$p" ] || continue
    local n
    n=$(basename "$p" .patch)
    [ -n "${listed[$n]:-}" ] || { echo "$p: not listed in $list"; status=1; }
  done
  local count=${#listed[@]}
  [ $status -eq 0 ] && echo "grade_mutants.sh: $count mutants listed; every patch applies"
  return $status
}

if [ "$mode" = check ]; then
  check && exit 0 || exit 2
fi
if [ "$mode" = plant ]; then
  [ -n "$plant_name" ] && [ -n "$plant_dir" ] || { echo "grade_mutants.sh: --plant NAME DIR" >&2; exit 2; }
  [ -f "$patches/$plant_name.patch" ] || { echo "grade_mutants.sh: no mutant $plant_name ($patches/$plant_name.patch)" >&2; exit 2; }
  [ ! -e "$plant_dir" ] || [ -z "$(ls -A "$plant_dir")" ] || { echo "grade_mutants.sh: $plant_dir exists and is not empty" >&2; exit 2; }
  copy_tree "$plant_dir"
  apply_patch "$plant_dir" "$root/$patches/$plant_name.patch"
  echo "Planted $plant_name in $plant_dir: cmake -S $plant_dir -B $plant_dir/build && cmake --build $plant_dir/build --target pathtracer"
  exit 0
fi

check > /dev/null || { check; exit 2; }
mkdir -p "$build_root"
grader="$root/build/bin/grader"
[ -x "$grader" ] || { echo "grade_mutants.sh: build the grader first (scripts/build.sh)" >&2; exit 2; }

# results.json -> "score max cases failed-case-names"
summarise() {
  python3 - "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
tests = r["tests"]
lost = [t["name"].split(": ", 1)[1] for t in tests if t["score"] < t["max_score"]]
print(f'{r["score"]:.2f} {sum(t["max_score"] for t in tests):g} {len(tests)} {",".join(lost) or "-"}')
PY
}
# The parts of a comma-separated list of case names (p3_x -> 3).
parts_of() { echo "$1" | tr ',' '\n' | sed -nE 's/^p([1-5])_.*/\1/p' | sort -u | tr '\n' ' '; }

build_pathtracer() {  # build DIR SOURCE: configure (once), then build the pathtracer only
  local dir=$1 src=$2
  [ -f "$dir/CMakeCache.txt" ] || cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF > "$dir.configure.log" 2>&1
  cmake --build "$dir" -j "$jobs" --target pathtracer > "$dir.build.log" 2>&1
}

status=0
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$SECONDS
# The commit graded: the tree is copied now, and HEAD may move during the run.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

# The reference build, every case.
echo "== reference"
set +e
"$grader" run -q -j "$jobs" -o "$build_root/reference.grade" > "$build_root/reference.grade.log" 2>&1
set -e
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
  set +e
  "$grader" run -q -j "$jobs" --pathtracer "$build_root/kit.build/bin/pathtracer" -o "$build_root/kit.grade" \
    > "$build_root/kit.grade.log" 2>&1
  set -e
  read -r score max n failed < <(summarise "$build_root/kit.grade/results.json")
  pct=$(python3 -c "print(f'{100*$score/$max:.1f}')")
  kit_row="| starter kit (all stubs) | $score / $max ($pct %) | $(echo "$failed" | tr ',' '\n' | grep -vc '^-$') of $n cases lose points |"
  python3 -c "import sys; sys.exit(0 if $score <= 0.10 * $max else 1)" || status=1
else
  kit_row="| starter kit (all stubs) | build failed (see $build_root/kit.build.build.log) | |"
  status=1
fi
echo "   $kit_row"

# One copy of the tree, built once; each mutant is applied, built
# (incrementally: only what the patch touches recompiles), its binary kept,
# and the patch reverted.
src="$build_root/src"
copy_tree "$src"
mkdir -p "$build_root/tree.build" "$build_root/bin"
build_pathtracer "$build_root/tree.build" "$src" || { echo "grade_mutants.sh: the unpatched copy does not build" >&2; exit 2; }
names=()
declare -A part_of=() description_of=() built=()
while read -r name part description; do
  if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " =~ " $name " ]]; then continue; fi
  names+=("$name")
  part_of[$name]=$part
  description_of[$name]=$description
  echo "== build $name"
  apply_patch "$src" "$root/$patches/$name.patch"
  if build_pathtracer "$build_root/tree.build" "$src"; then
    cp "$build_root/tree.build/bin/pathtracer" "$build_root/bin/$name"
    built[$name]=1
  else
    cp "$build_root/tree.build.build.log" "$build_root/$name.build.log"
  fi
  apply_patch "$src" "$root/$patches/$name.patch" -R
done < <(mutant_lines)

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
  set +e
  "$grader" run -q -j "$jobs" --pathtracer "$build_root/bin/$name" -o "$build_root/$name.grade" > "$build_root/$name.grade.log" 2>&1
  set -e
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
  echo "in [mutants.txt](mutants.txt)). Every build is graded on every case; a mutant is caught"
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
