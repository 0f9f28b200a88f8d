#!/usr/bin/env bash
# How long a student waits on a fresh kit: from scripts/run.sh's start to
# its first image, to the end of run.sh, and then to the end of the first
# part check. Prints the figures; a measurement, not a test.
#
#   instructors/starter_kit/time_first_steps.sh [--solved-parts PARTS] [--tree DIR] [--check CMD] WORK_DIR
#
#   --solved-parts PARTS  the kit's given parts (1-5: the kit for Project 3-2)
#   --tree DIR            the tree whose generator makes the kit (default: this
#                         one), e.g. a checkout of an earlier commit to compare
#   --check CMD           the first part check, run in the kit after run.sh
#                         (default: what the kit's first stubbed part's README
#                         gives, `scripts/check.sh N`)
#   WORK_DIR              made empty; the kit goes to WORK_DIR/kit
#
# The builds use every core (as the kit's scripts do); say how busy the
# machine was (the load average is printed before and after).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
tree=$here solved="" check=""
while [ $# -gt 1 ]; do
  case "$1" in
    --solved-parts) solved=$2; shift 2 ;;
    --tree) tree=$(cd "$2" && pwd); shift 2 ;;
    --check) check=$2; shift 2 ;;
    *) break ;;
  esac
done
[ $# -eq 1 ] || { sed -n '2,17p' "$0" >&2; exit 2; }
work=$1
rm -rf "$work"
mkdir -p "$work"
kit=$work/kit

now() { date +%s.%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.0f", b - a }'; }
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)"

t0=$(now)
"$tree/instructors/starter_kit/make_starter_kit.py" ${solved:+--solved-parts "$solved"} "$kit" >/dev/null
t_kit=$(now)

# run.sh, its lines stamped as they come; the first image is the line that
# says where the render went.
start=$(now)
first_image=""
while IFS= read -r line; do
  printf '%s\n' "$line" >>"$work/run_sh.log"
  if [ -z "$first_image" ] && [[ "$line" == Rendered* ]]; then
    first_image=$(now)
  fi
done < <(cd "$kit" && scripts/run.sh 2>&1; echo "run.sh exit status $?")
end=$(now)

if [ -z "$check" ]; then
  first=1
  for n in 1 2 3 4 5 6 7 8 9; do
    if ! grep -qx "$n" "$kit/solved_parts.txt" 2>/dev/null; then first=$n; break; fi
  done
  check="scripts/check.sh $first"
fi
c0=$(now)
(cd "$kit" && bash -c "$check") >"$work/check.log" 2>&1 || true
c1=$(now)

echo "tree: $tree ($(git -C "$tree" rev-parse --short HEAD 2>/dev/null || echo 'not a git checkout'))"
echo "kit: ${solved:+parts $solved given solved, }written in $(seconds "$t0" "$t_kit") s"
if [ -n "$first_image" ]; then
  echo "scripts/run.sh: first image after $(seconds "$start" "$first_image") s, done after $(seconds "$start" "$end") s"
else
  echo "scripts/run.sh: no 'Rendered' line (see $work/run_sh.log), done after $(seconds "$start" "$end") s"
fi
echo "first part check, '$check': $(seconds "$c0" "$c1") s ($(grep -E 'tests passed|No tests were found|FAILED: no test' "$work/check.log" | head -1))"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "logs: $work/run_sh.log, $work/check.log"
