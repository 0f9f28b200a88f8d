#!/usr/bin/env bash
# The catalogues' check in the test suite, small enough to run every time:
# several legal variants planted together in one copy of the tree (they
# touch different places, and correct code combined is still correct) must
# score full marks, and a mutant planted on top of them must still lose
# points. One copy, one build of its pathtracer, one incremental rebuild.
# The mutant is graded only on the cases of its own part and later (of the
# parts GRADER_RUN_ARGS name): `pathtracer --part N` runs stages 1..N, so a
# bug in a later stage cannot change an earlier part's image.
#
#   instructors/legal_variants/graded_together.sh WORK [--variant NAME]... [--mutant NAME] [-- GRADER_RUN_ARGS...]
#
# Exit 0 when the variants' build passes every graded case and the mutant's
# (if any) loses points; 1 otherwise, with the grader's table; 2 for bad
# usage, a patch that does not apply or a build that fails.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
[ $# -ge 1 ] || { sed -n '2,16p' "$0"; exit 2; }
work=$(realpath -m "$1")
shift
variants=() mutant="" grader_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --variant) variants+=("$2"); shift 2 ;;
    --mutant) mutant=$2; shift 2 ;;
    --) shift; grader_args=("$@"); break ;;
    *) echo "graded_together.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
grader="$root/build/bin/grader"
[ -x "$grader" ] || { echo "graded_together.sh: build the grader first (scripts/build.sh)" >&2; exit 2; }

# The shared machinery's tree copy and patch application.
tool=graded_together.sh noun=patch list=/dev/null patches=/dev/null
# shellcheck source=../patch_catalogue.sh
source instructors/patch_catalogue.sh

src="$work/src"
copy_tree "$src"
for v in "${variants[@]}"; do
  apply_patch "$src" "$root/instructors/legal_variants/patches/$v.patch" \
    || { echo "graded_together.sh: variant $v does not apply on top of the others" >&2; exit 2; }
done
# Built inside the copy, through ccache where it is installed (as
# scripts/build.sh does): the files no patch touches are then cache hits of
# this tree's own build (same paths relative to the build folder).
ccache=OFF
command -v ccache >/dev/null 2>&1 && ccache=ON
build() {
  [ -f "$src/build/CMakeCache.txt" ] ||
    cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF -DPT_CCACHE=$ccache \
      > "$work/configure.log" 2>&1
  cmake --build "$src/build" -j "$(nproc 2>/dev/null || echo 2)" --target pathtracer > "$work/build.log" 2>&1 ||
    { tail -20 "$work/build.log"; echo "graded_together.sh: the build failed ($work/build.log)" >&2; exit 2; }
}
build
status=0
echo "== legal variants together: ${variants[*]:-none}"
if "$grader" run -q --pathtracer "$src/build/bin/pathtracer" -o "$work/variants.grade" "${grader_args[@]}" \
     > "$work/variants.log" 2>&1; then
  echo "   full marks"
else
  cat "$work/variants.log"
  echo "graded_together.sh: the legal variants lost points (see above)" >&2
  status=1
fi
if [ -n "$mutant" ]; then
  apply_patch "$src" "$root/instructors/mutants/patches/$mutant.patch" \
    || { echo "graded_together.sh: mutant $mutant does not apply on top of the variants" >&2; exit 2; }
  build
  # Its own part and later: drop the earlier parts' --part options (or name
  # the later parts when none was given).
  first=$(first_part_of_patch "$root/instructors/mutants/patches/$mutant.patch")
  mutant_args=() parts_named=0
  i=0
  while [ $i -lt ${#grader_args[@]} ]; do
    a=${grader_args[$i]}
    if [ "$a" = --part ] && [ $((i + 1)) -lt ${#grader_args[@]} ]; then
      parts_named=1
      n=${grader_args[$((i + 1))]}
      [ "$n" -lt "$first" ] || mutant_args+=(--part "$n")
      i=$((i + 2))
    else
      mutant_args+=("$a")
      i=$((i + 1))
    fi
  done
  if [ $parts_named = 0 ]; then
    for n in $(seq "$first" 9); do mutant_args+=(--part "$n"); done
  elif ! printf '%s\n' "${mutant_args[@]}" | grep -qx -- --part; then
    echo "graded_together.sh: mutant $mutant is in part $first, after every part graded" >&2
    exit 2
  fi
  echo "== mutant $mutant on top of them (parts $first and later)"
  if "$grader" run -q --pathtracer "$src/build/bin/pathtracer" -o "$work/mutant.grade" "${mutant_args[@]}" \
       > "$work/mutant.log" 2>&1; then
    cat "$work/mutant.log"
    echo "graded_together.sh: mutant $mutant was not caught" >&2
    status=1
  else
    grep -E "cases passed; score" "$work/mutant.log" | sed 's/^/   caught: /'
  fi
fi
exit $status
