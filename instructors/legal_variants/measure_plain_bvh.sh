#!/usr/bin/env bash
# What a plain binary BVH built the way the course suggests achieves on
# each case from part 2 on: the baseline of part 2's cost check. Builds the
# legal variants bvh_midpoint and bvh_median (instructors/patch_catalogue.sh),
# renders every case of grader/cases.txt with part >= 2 with each at three
# seeds (the command `grader compare --list` prints, with --stats-json), and
# writes reference_images/plain_bvh_costs.json: per case, the larger over
# the two builds of the median closest_tests_per_query, shadow_tests_per_query,
# shadow rays per closest-hit query and tests_per_ray, with the commit and
# date. For comparison it also measures the other legal variants whose
# queries cost differently (bvh_leaf_1, bvh_leaf_8, bvh_pointer_tree,
# shadow_closest_hit, cos_after_shadow_ray) and prints every build's
# figures beside the reference's (reference_images/<case>/meta.json).
#
#   instructors/legal_variants/measure_plain_bvh.sh [--seeds 1,2,3] [--no-compare] [--out FILE] [--build-root DIR] [-j N]
#                                                 [--hidden]
#
# --hidden measures the hidden cases instead (instructors/hidden_cases/:
# their list, their references, and --out their plain_bvh_costs.json).
#
# About 4 min on 2 busy cores (seven builds, about a minute; the 35 cases
# at three seeds each); without the comparison builds about 2 min. Exit
# status 0 when the file is written, 2 for bad usage or a build that fails.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
tool=measure_plain_bvh.sh
noun=variant
list=instructors/legal_variants/variants.txt
patches=instructors/legal_variants/patches
build_root="$root/build/plain_bvh"
table=/dev/null
jobs=$(nproc 2>/dev/null || echo 2)
only=()
mode=grade
plant_name="" plant_dir=""
seeds=1,2,3
out="$root/reference_images/plain_bvh_costs.json"
cases_args=()
compare=(bvh_leaf_1 bvh_leaf_8 bvh_pointer_tree shadow_closest_hit cos_after_shadow_ray)
. instructors/patch_catalogue.sh
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) [ $# -ge 2 ] && [[ "$2" =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "$tool: --seeds 1,2,3" >&2; exit 2; }
             seeds=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || { echo "$tool: --out FILE" >&2; exit 2; }
           out=$(realpath -m "$2"); shift 2 ;;
    --no-compare) compare=(); shift ;;
    --hidden) cases_args=(--cases "$root/instructors/hidden_cases/cases.txt"
                          --references "$root/instructors/hidden_cases/references")
              out="$root/instructors/hidden_cases/references/plain_bvh_costs.json"; shift ;;
    --build-root|-j) catalogue_option "$@" || exit 2; shift "$catalogue_shift" ;;
    -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
    *) echo "$tool: unknown argument $1" >&2; exit 2 ;;
  esac
done
only=(bvh_midpoint bvh_median "${compare[@]}")
catalogue_start
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
catalogue_build_all
args=()
for name in "${names[@]}"; do
  [ -n "${built[$name]:-}" ] || { echo "$tool: $name does not build ($build_root/$name.build.log)" >&2; exit 2; }
  args+=(--build "$name=$build_root/bin/$name")
done
python3 instructors/legal_variants/query_costs.py "${args[@]}" --baseline bvh_midpoint,bvh_median \
  --out "$out" --seeds "$seeds" -j "$jobs" --work "$build_root/renders" --commit "$commit" \
  --grader "$grader" "${cases_args[@]}"
