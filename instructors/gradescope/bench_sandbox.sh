#!/usr/bin/env bash
# What the sandbox costs: grades the reference's stages/ through the real
# package (make_autograder.sh, setup.sh, run_autograder) with the sandbox
# (AUTOGRADER_SANDBOX=auto) and without it (AUTOGRADER_SANDBOX=none, which
# exists for this measurement only: no sandbox at all), in interleaved
# rounds, and prints each run's wall time and the ratio of the medians.
#
#   instructors/gradescope/bench_sandbox.sh [--rounds N] [--grader-args "ARGS"] [--keep DIR]
#
#   --rounds N         rounds of one run each way (default 3), the order
#                      alternating from round to round
#   --grader-args ARGS the cases graded (default "--part 1": six cases)
#   --keep DIR         the AUTOGRADER_ROOT to use and keep (default: a
#                      temporary one under /tmp, deleted at the end)
#
# Needs root (the sandbox's accounts) and the references of the cases in
# reference_images/. Run it on a machine doing nothing else: it measures
# time. Each run rebuilds the stages (the submission's files are new) and
# links the pathtracer, then grades.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
rounds=3
grader_args="--part 1"
keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds=$2; shift 2 ;;
    --grader-args) grader_args=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "bench_sandbox: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "bench_sandbox: --rounds $rounds: expected a positive number" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "bench_sandbox: needs root (the sandbox's accounts)" >&2; exit 2; }

. "$here/local_package.sh"
local_package bench_sandbox "$keep"
sub=$base/submission
rm -rf "$sub"
mkdir -p "$sub/kit"
cp -R "$root/stages" "$sub/kit/stages"

declare -A times
one_run() {  # one_run MODE ROUND
  local mode=$1 t0 t1 score
  t0=$(date +%s.%N)
  (cd "$ag" && AUTOGRADER_ROOT=$ag AUTOGRADER_SUBMISSION=$sub AUTOGRADER_SANDBOX=$mode GRADER_ARGS="$grader_args" \
    ./run_autograder) >"$base/run-$mode-$2.log" 2>&1
  t1=$(date +%s.%N)
  score=$(python3 - "$ag/results/results.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
print("%g of %g" % (d["score"], sum(t.get("max_score") or 0 for t in d.get("tests", []))))
EOF
  )
  times[$mode]+="$(python3 -c "print(f'{$t1 - $t0:.2f}')") "
  printf 'round %d  %-5s %7.2f s  (build %s s, grading %s s; score %s; %s)\n' "$2" "$mode" \
    "$(python3 -c "print($t1 - $t0)")" "$(sed -n 's/^== Build: \([0-9]*\) s$/\1/p' "$base/run-$mode-$2.log")" \
    "$(sed -n 's/^== Grading: \([0-9]*\) s$/\1/p' "$base/run-$mode-$2.log")" "$score" \
    "$(grep -m1 '^== Sandbox' "$base/run-$mode-$2.log" | sed 's/^== //')"
}
echo "bench_sandbox: $rounds rounds, grader arguments: $grader_args; load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
for r in $(seq 1 "$rounds"); do
  if [ $((r % 2)) = 1 ]; then
    one_run auto "$r"
    one_run none "$r"
  else
    one_run none "$r"
    one_run auto "$r"
  fi
done
python3 - "${times[auto]}" "${times[none]}" <<'EOF'
import statistics, sys
auto = [float(x) for x in sys.argv[1].split()]
none = [float(x) for x in sys.argv[2].split()]
ma, mn = statistics.median(auto), statistics.median(none)
print(f"median with the sandbox {ma:.2f} s, without {mn:.2f} s: ratio {ma / mn:.3f}")
EOF
echo "bench_sandbox: load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
