#!/usr/bin/env bash
# Side-by-side ray-query speed of the path tracer's BVH and Intel Embree 3 on
# identical work: for each scene, ray_bench writes the triangles and three ray
# sets (primary, diffuse, shadow), embree_bench and ray_bench both trace them
# on one thread, and one Markdown table of the medians is printed.
#
#   instructors/bench/compare_embree.sh [--runs N] [--reps R] [--rays N] [--clock wall|cpu] [SCENE.dae ...]
#
# Each binary is run N times (default 3) per scene and ray set; each run
# reports the best of R passes (default 5); the table shows the median of
# the N runs. Hit counts and the sum of hit distances must agree between the
# two engines: otherwise the check column says MISMATCH and the exit status
# is 1. Progress goes to stderr, the report (Markdown) to stdout. Files go
# to build/bench-out/ (PT_BUILD_DIR=DIR uses another build folder).
# --clock cpu times both engines by the calling thread's CPU time instead of
# the wall clock (embree_bench is then compiled from a copy of its source
# with that one change, as build/embree_bench_cpu): on a machine shared with
# other jobs the wall clock counts the time spent waiting for a core, the
# CPU time does not. Both builds run on one thread, so their CPU time is
# their time.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

runs=3
reps=5
rays=200000
clock=wall
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs=${2:?--runs needs a value}; shift 2 ;;
    --reps) reps=${2:?--reps needs a value}; shift 2 ;;
    --rays) rays=${2:?--rays needs a value}; shift 2 ;;
    --clock) clock=${2:?--clock needs a value}; shift 2 ;;
    -h|--help) sed -n '2,20p' "$root/instructors/bench/compare_embree.sh" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "compare_embree.sh: error: unknown option $1" >&2; exit 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
case "$clock" in wall|cpu) ;; *) echo "compare_embree.sh: error: --clock takes wall or cpu, got '$clock'" >&2; exit 2 ;; esac
for v in "$runs" "$reps" "$rays"; do
  case "$v" in ''|*[!0-9]*|0) echo "compare_embree.sh: error: --runs, --reps and --rays take positive integers, got '$v'" >&2; exit 2 ;; esac
done

# Default scenes: the project's mesh scenes, else the course's.
if [ ${#scenes[@]} -eq 0 ]; then
  for s in scenes/CBbunny.dae scenes/CBdragon.dae scenes/CBdragon_large.dae; do
    [ -f "$s" ] && scenes+=("$s")
  done
  if [ ${#scenes[@]} -eq 0 ]; then
    for s in ../shared/cs184-scenes/CBbunny.dae ../shared/cs184-scenes/cow.dae; do
      [ -f "$s" ] && scenes+=("$s")
    done
  fi
  [ ${#scenes[@]} -gt 0 ] || { echo "compare_embree.sh: error: no mesh scene found; name the scene files" >&2; exit 2; }
fi
for s in "${scenes[@]}"; do
  [ -f "$s" ] || { echo "compare_embree.sh: error: $s: no such scene file" >&2; exit 2; }
done
command -v python3 >/dev/null || { echo "compare_embree.sh: error: python3 is needed for the table" >&2; exit 2; }

# ---- Build both binaries ----
# PT_BUILD_DIR: the project's build folder (default build/).
bdir=${PT_BUILD_DIR:-build}
embree=$bdir/embree_bench
bench=$bdir/bin/ray_bench
echo "building $embree ..." >&2
../shared/bench/build.sh "$embree" >&2
if [ "$clock" = cpu ]; then
  # The same source with its steady_clock replaced by this thread's CPU time.
  mkdir -p "$bdir/bench-out"
  python3 - ../shared/bench/embree_bench.cpp "$bdir/bench-out/embree_bench_cpu.cpp" <<'PY'
import sys
s = open(sys.argv[1]).read()
old_clock = "using Clock = std::chrono::steady_clock;"
old_seconds = "static double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }"
if old_clock not in s or old_seconds not in s:
    sys.exit("compare_embree.sh: error: embree_bench.cpp no longer has the clock lines --clock cpu replaces")
s = s.replace(old_clock, "#include <ctime>\nstruct Clock { using time_point = double; static double now() { timespec ts; "
              "clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec); } };")
s = s.replace(old_seconds, "static double seconds(double a, double b) { return b - a; }")
open(sys.argv[2], "w").write(s)
PY
  embree=${embree}_cpu
  g++ -O3 -march=native -std=c++17 "$bdir/bench-out/embree_bench_cpu.cpp" -lembree3 -o "$embree" >&2
  echo "$embree (CPU-time clock)" >&2
fi
echo "building $bench ..." >&2
[ -f "$bdir/CMakeCache.txt" ] || cmake -S . -B "$bdir" >&2
cmake --build "$bdir" -j2 --target ray_bench >&2

# ---- Run ----
results=$bdir/bench-out/results
rm -rf "$results"
mkdir -p "$results"
cmdlog="$results/commands.txt"
: >"$cmdlog"

log_once() {  # records a command line (first run only)
  [ "$1" = 1 ] || return 0
  shift
  printf '%s\n' "$*" >>"$cmdlog"
}

idx=0
for scene in "${scenes[@]}"; do
  idx=$((idx + 1))
  stem=$(basename "$scene" .dae)
  key="$idx-$stem"
  out=$bdir/bench-out/$key
  mkdir -p "$results/$key"
  echo "$scene:" >&2
  for run in $(seq 1 "$runs"); do
    echo "  run $run/$runs: ray_bench" >&2
    log_once "$run" "$bench" "$scene" --out "$out" --rays "$rays" --reps "$reps" --clock "$clock"
    "$bench" "$scene" --out "$out" --rays "$rays" --reps "$reps" --clock "$clock" >"$results/$key/ours.$run.txt"
    for set in primary diffuse shadow; do
      # Skip empty sets (no lights: no shadow rays). Bytes 8-15 hold the count.
      n=$(od -An -t u8 -j 8 -N 8 "$out/$set.rays" | tr -d ' ')
      [ "${n:-0}" -gt 0 ] || continue
      echo "  run $run/$runs: embree_bench $set" >&2
      log_once "$run" "$embree" "$out/$stem.tris" "$out/$set.rays" --reps "$reps" --quality medium
      "$embree" "$out/$stem.tris" "$out/$set.rays" --reps "$reps" --quality medium >"$results/$key/embree.$set.$run.txt"
    done
  done
  printf '%s\n' "$scene" >"$results/$key/scene"
done

# ---- Report ----
model=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)
cpus=$(nproc 2>/dev/null || echo '?')
compiler=$(c++ --version 2>/dev/null | head -1)
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$bdir/CMakeCache.txt" | head -1)
native=$(sed -n 's/^PT_NATIVE:[A-Z]*=//p' "$bdir/CMakeCache.txt" | head -1)
commit=$(git rev-parse --short HEAD 2>/dev/null || echo 'unknown')
dirty=$(git status --porcelain 2>/dev/null | head -1)

echo "## Ray queries: pathtracer BVH vs Embree (one thread)"
echo
echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "- machine: ${model:-unknown} ($cpus logical CPUs)"
echo "- compiler: $compiler; project build: ${build_type:-?}, PT_NATIVE=${native:-OFF}; embree_bench: -O3 -march=native"
echo "- source: commit $commit${dirty:+ plus uncommitted changes}"
echo "- each figure: median of $runs runs of the best of $reps passes; $rays primary rays per scene"
echo "- clock: $([ "$clock" = cpu ] && echo "the calling thread's CPU time (--clock cpu)" || echo "wall clock (steady_clock)")"
echo "- load average at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?') on $(nproc 2>/dev/null || echo '?') CPUs"
echo
status=0
python3 - "$results" "$runs" <<'PY' || status=$?
import glob, os, statistics, sys

results, runs = sys.argv[1], int(sys.argv[2])

def blocks(path):
    """key: value blocks separated by blank lines."""
    out, cur = [], {}
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if not line.strip():
                if cur: out.append(cur); cur = {}
                continue
            k, _, v = line.partition(":")
            cur[k.strip()] = v.strip()
    if cur: out.append(cur)
    return out

def med(values):
    return statistics.median(values) if values else float("nan")

def fmt(x, digits=2):
    return "n/a" if x != x else f"{x:.{digits}f}"

def fmt_ms(x):
    return fmt(x, 3 if x < 1 else 2 if x < 10 else 1)

def ratio(a, b):
    return a / b if b > 0 else float("nan")

rows, mismatches, engine = [], [], None
for d in sorted(glob.glob(os.path.join(results, "*/")), key=lambda p: int(os.path.basename(p.rstrip("/")).split("-")[0])):
    scene = open(os.path.join(d, "scene")).read().strip()
    ours = {}  # set -> list of blocks, one per run
    for r in range(1, runs + 1):
        p = os.path.join(d, f"ours.{r}.txt")
        if not os.path.exists(p): continue
        for b in blocks(p):
            ours.setdefault(b["ray_set"], []).append(b)
            engine = engine or b.get("engine")
    for s in ("primary", "diffuse", "shadow"):
        emb = []
        for r in range(1, runs + 1):
            p = os.path.join(d, f"embree.{s}.{r}.txt")
            if os.path.exists(p): emb += blocks(p)
        if s not in ours or not emb: continue
        o, e = ours[s], emb
        f = lambda bl, k: med([float(b[k]) for b in bl])
        row = dict(scene=os.path.basename(scene), tris=int(o[0]["triangles"]), set=s, rays=int(o[0]["rays"]),
                   oc=f(o, "closest_mrays_per_s"), ec=f(e, "closest_mrays_per_s"),
                   oa=f(o, "anyhit_mrays_per_s"), ea=f(e, "anyhit_mrays_per_s"),
                   ob=f(o, "build_ms"), eb=f(e, "build_ms"),
                   obt=f(o, "build_all_threads_ms") if "build_all_threads_ms" in o[0] else float("nan"),
                   threads=o[0].get("build_threads", "?"),
                   tests=f(o, "closest_tests_per_ray"), nodes=f(o, "closest_nodes_per_ray"))
        # Same work, same answers: compare the first run of each.
        problems = []
        oh, eh = int(o[0]["closest_hits"]), int(e[0]["closest_hits"])
        ot, et = float(o[0]["closest_sum_t"]), float(e[0]["closest_sum_t"])
        oo, eo = int(o[0]["occluded"]), int(e[0]["occluded"])
        if oh != eh: problems.append(f"hits {oh} vs {eh}")
        if abs(ot - et) > 1e-4 * max(abs(et), 1e-30) and not (ot == 0 and et == 0): problems.append(f"sum_t {ot:.6e} vs {et:.6e}")
        if oo != eo: problems.append(f"occluded {oo} vs {eo}")
        row["check"] = "ok" if not problems else "**MISMATCH** " + ", ".join(problems)
        if problems: mismatches.append(f"{row['scene']} {s}: " + ", ".join(problems))
        rows.append(row)

print(f"ours: {engine}  ")
print("Embree: embree_bench, build quality medium, 1 thread")
print()
threads = rows[0]["threads"] if rows else "?"
print(f"| scene | triangles | ray set | rays | closest ours Mrays/s | closest Embree | ratio | any-hit ours Mrays/s | any-hit Embree | ratio | build ours ms | build Embree ms | ratio | build ours ms, {threads} threads | tests/ray | nodes/ray | check |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
for r in rows:
    print(f"| {r['scene']} | {r['tris']} | {r['set']} | {r['rays']} | {fmt(r['oc'])} | {fmt(r['ec'])} | {fmt(ratio(r['oc'], r['ec']))} "
          f"| {fmt(r['oa'])} | {fmt(r['ea'])} | {fmt(ratio(r['oa'], r['ea']))} | {fmt_ms(r['ob'])} | {fmt_ms(r['eb'])} | {fmt(ratio(r['ob'], r['eb']))} | {fmt_ms(r['obt'])} "
          f"| {fmt(r['tests'])} | {fmt(r['nodes'])} | {r['check']} |")
print()
print("Ratios are ours / Embree (above 1: ours is faster for speed, slower for build time); both builds on one")
print(f"thread, and ours again with all {threads} threads, as the pathtracer builds. tests/ray and nodes/ray are")
print("triangle tests and BVH nodes visited per closest-hit query (all rays of the set, misses included).")
print()
print("Targets: closest-hit >= 0.9x Embree on primary and >= 0.6x on diffuse rays; occlusion >= 0.8x on")
print("shadow rays; build time (one thread each) <= 2x Embree medium; <= 2 triangle tests per primary ray on the bunny.")
print()
for r in rows:
    t = []
    if r["set"] == "primary": t.append(("closest >= 0.9x", ratio(r["oc"], r["ec"]) >= 0.9))
    if r["set"] == "diffuse": t.append(("closest >= 0.6x", ratio(r["oc"], r["ec"]) >= 0.6))
    if r["set"] == "shadow": t.append(("any-hit >= 0.8x", ratio(r["oa"], r["ea"]) >= 0.8))
    if r["set"] == "primary": t.append(("build <= 2x", ratio(r["ob"], r["eb"]) <= 2))
    if r["set"] == "primary" and "bunny" in r["scene"].lower(): t.append(("tests/ray <= 2", r["tests"] <= 2))
    print(f"- {r['scene']} {r['set']}: " + "; ".join(f"{n} {'met' if ok else 'NOT met'}" for n, ok in t))
print()
if mismatches:
    print("**MISMATCH: the two engines disagree on identical rays:**")
    for m in mismatches: print(f"- {m}")
    for m in mismatches: print(f"MISMATCH: {m}", file=sys.stderr)
    sys.exit(1)
print("All hit counts, sums of hit distances and occlusion counts agree with Embree.")
PY
echo
echo "Commands (from $root; run $runs times each):"
echo
echo '```'
echo "../shared/bench/build.sh ${embree%_cpu}"
[ "$clock" = cpu ] && echo "(and $embree: embree_bench.cpp with the CPU-time clock, see --clock in this script)"
echo "cmake --build $bdir -j2 --target ray_bench"
cat "$cmdlog"
echo '```'
exit $status
