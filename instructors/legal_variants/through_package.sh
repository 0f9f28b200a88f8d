#!/usr/bin/env bash
# The legal variants through the Gradescope package, as a student's
# submission goes: each variant's stages/ (the reference's, its patch
# applied: every patch touches only stages/ .cpp and .h files, which the
# intake takes) is submitted to run_autograder (make_autograder.sh, then
# setup.sh, once), which takes its sources, builds them in the build
# sandbox and grades every public and hidden case with the renders
# sandboxed. The reference's stages/ first. Prints one line per build and
# writes the table to --table.
#
#   sudo instructors/legal_variants/through_package.sh [--seed N] [--only NAME]... [--keep DIR] [--table FILE]
#
#   --seed N    the grader's seed (default 1)
#   --only NAME only this variant (repeatable; the reference always)
#   --keep DIR  the AUTOGRADER_ROOT to use and keep (default: a temporary
#               one under /tmp, deleted at the end); a package already set
#               up there is used again
#   --table F   default instructors/legal_variants/through_package.md
#
# Needs root (the sandbox's accounts). About a minute per build on 2 cores.
# Exit status: 0 when every build gets full marks; 1 otherwise; 2 for bad
# usage or a package that could not be made.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
seed=1 keep="" table=$root/instructors/legal_variants/through_package.md only=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seed) seed=$2; shift 2 ;;
    --only) only+=("$2"); shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    --table) table=$(realpath -m "$2"); shift 2 ;;
    -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "through_package: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ "$seed" =~ ^[0-9]+$ ]] || { echo "through_package: --seed $seed: expected a number" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "through_package: needs root (the sandbox's accounts)" >&2; exit 2; }

. "$root/instructors/gradescope/local_package.sh"
local_package through_package "$keep"

names=(reference)
while read -r name _; do
  [ -n "$name" ] || continue
  if [ ${#only[@]} -gt 0 ]; then
    printf '%s\n' "${only[@]}" | grep -qxF "$name" || continue
  fi
  names+=("$name")
done < <(grep -v '^\s*#' "$root/instructors/legal_variants/variants.txt" | awk 'NF >= 2 { print $1, $2 }')

status=0 rows=() t_start=$SECONDS
for name in "${names[@]}"; do
  sub=$base/submissions/$name
  rm -rf "$sub"
  mkdir -p "$sub/kit"
  cp -R "$root/stages" "$sub/kit/stages"
  if [ "$name" != reference ]; then
    patch -s -d "$sub/kit" -p1 <"$root/instructors/legal_variants/patches/$name.patch" ||
      { echo "through_package: $name: the patch does not apply" >&2; exit 2; }
  fi
  t0=$SECONDS
  (cd "$ag" && AUTOGRADER_ROOT=$ag AUTOGRADER_SUBMISSION=$sub GRADER_ARGS="--seed $seed" ./run_autograder) \
    >"$base/$name.log" 2>&1 || true
  line=$(python3 - "$ag/results/results.json" <<'EOF'
import json, sys
try:
    d = json.load(open(sys.argv[1]))
except (OSError, ValueError):
    print("- - none")
    sys.exit(0)
tests = [t for t in d.get("tests", []) if t.get("max_score")]
full = sum(t["max_score"] for t in tests)
lost = [t["name"] for t in tests if t.get("score", 0) < t["max_score"] - 1e-9]
print(f'{float(d["score"]):g} {full:g} {"; ".join(lost) if lost else "-"}')
EOF
  )
  read -r score full lost <<<"$line"
  mode=$(sed -n 's/^== Sandbox: \([a-z]*\).*/\1/p' "$base/$name.log" | head -1)
  printf '%-28s %8s / %-6s %4d s  %s  lost: %s\n' "$name" "$score" "$full" $((SECONDS - t0)) "${mode:-?}" "$lost"
  rows+=("| $name | $score / $full | ${mode:-?} | $((SECONDS - t0)) s | $lost |")
  [ "$lost" = "-" ] && [ "$score" = "$full" ] || status=1
done

commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
{
  echo "# The legal variants through the Gradescope package"
  echo
  echo "Each build's \`stages/\` submitted to \`run_autograder\` (\`make_autograder.sh\`, \`setup.sh\` once): sources only, the build and every render in the sandbox, every public and hidden case, grader seed $seed. Made by \`instructors/legal_variants/through_package.sh --seed $seed\` at commit $commit on $(date -u +%Y-%m-%dT%H:%M:%SZ) ($(( (SECONDS - t_start + 30) / 60 )) min)."
  echo
  echo "| build | score | sandbox | time | tests that lost points |"
  echo "|---|---:|---|---:|---|"
  printf '%s\n' "${rows[@]}"
} >"$table"
echo "through_package: table in $table"
exit $status
