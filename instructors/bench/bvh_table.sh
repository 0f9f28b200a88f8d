#!/usr/bin/env bash
# The write-up's BVH table: the same small render without the BVH (--part 1,
# every ray tests every primitive) and with it (--part 2), per scene, as one
# Markdown table of render times, speed-up, Mrays/s and tests per ray.
#
#   instructors/bench/bvh_table.sh [-r W H] [-s N] [-t N] [--repeat N] [SCENE.dae ...]
#
# Defaults: -r 160 120 -s 1 -t 1 (part 1 is slow on big meshes), part 2 run
# --repeat 5 times (median render time; part 1 runs once), and three
# scenes: CBspheres_lambertian, the bunny and the dragon from scenes/ (the
# course's bunny and cow from ../shared/cs184-scenes/ when the project's
# meshes are absent). The figures come from the pathtracer's --stats-json;
# its console output is kept in build/bench-out/bvh_table/.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

width=160 height=120 spp=1 threads=1 repeat=5
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    -r) [ $# -ge 3 ] || { echo "bvh_table.sh: error: -r needs a width and a height" >&2; exit 2; }
        width=$2; height=$3; shift 3 ;;
    -s|-t|--repeat) [ $# -ge 2 ] || { echo "bvh_table.sh: error: $1 needs a value" >&2; exit 2; }
        case "$1" in -s) spp=$2 ;; -t) threads=$2 ;; *) repeat=$2 ;; esac; shift 2 ;;
    -h|--help) sed -n '2,13p' "$root/instructors/bench/bvh_table.sh" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bvh_table.sh: error: unknown option $1" >&2; exit 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
for v in "$width" "$height" "$spp" "$threads" "$repeat"; do
  case "$v" in ''|*[!0-9]*|0) echo "bvh_table.sh: error: -r, -s, -t and --repeat take positive integers, got '$v'" >&2; exit 2 ;; esac
done

pick() {  # first existing file among the arguments
  for f in "$@"; do [ -f "$f" ] && { echo "$f"; return; }; done
}
if [ ${#scenes[@]} -eq 0 ]; then
  course=../shared/cs184-scenes
  for s in "$(pick scenes/CBspheres_lambertian.dae "$course/CBspheres_lambertian.dae")" \
           "$(pick scenes/CBbunny.dae "$course/CBbunny.dae")" \
           "$(pick scenes/CBdragon.dae "$course/cow.dae")"; do
    [ -n "$s" ] && scenes+=("$s")
  done
  [ ${#scenes[@]} -gt 0 ] || { echo "bvh_table.sh: error: no scene found; name the scene files" >&2; exit 2; }
fi
for s in "${scenes[@]}"; do
  [ -f "$s" ] || { echo "bvh_table.sh: error: $s: no such scene file" >&2; exit 2; }
done
command -v python3 >/dev/null || { echo "bvh_table.sh: error: python3 is needed for the table" >&2; exit 2; }

# PT_BUILD_DIR: the project's build folder (default build/).
bdir=${PT_BUILD_DIR:-build}
pathtracer=$bdir/bin/pathtracer
echo "building $pathtracer ..." >&2
[ -f "$bdir/CMakeCache.txt" ] || cmake -S . -B "$bdir" >&2
cmake --build "$bdir" -j2 --target pathtracer >&2

out=$bdir/bench-out/bvh_table
rm -rf "$out"
mkdir -p "$out"
jsons=()
commands=()
idx=0
for scene in "${scenes[@]}"; do
  idx=$((idx + 1))
  stem=$(basename "$scene" .dae)
  # Part 1 once (long enough to time); part 2 lasts milliseconds, so it is
  # run $repeat times and the run with the median render time is reported.
  for part in 1 2; do
    n=1
    [ "$part" = 2 ] && n=$repeat
    group=()
    for k in $(seq 1 "$n"); do
      base="$out/$idx-$stem.part$part.$k"
      cmd=("$pathtracer" --part "$part" -r "$width" "$height" -s "$spp" -t "$threads" --no-progress
           -f "$base.png" --stats-json "$base.json" "$scene")
      echo "$scene: part $part ($k/$n) ..." >&2
      if ! "${cmd[@]}" >"$base.log" 2>&1; then
        echo "bvh_table.sh: error: the pathtracer failed on $scene (part $part); see $base.log:" >&2
        tail -3 "$base.log" >&2
        exit 1
      fi
      group+=("$base.json")
      [ "$k" = 1 ] && commands+=("${cmd[*]}")
    done
    jsons+=("$(IFS=,; echo "${group[*]}")")
  done
done

echo "## Without and with the BVH (${width}x${height}, $spp sample(s) per pixel, $threads thread(s))"
echo
echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "- machine: $(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1) ($(nproc) logical CPUs)"
echo "- compiler: $(c++ --version 2>/dev/null | head -1)"
echo
python3 - "${jsons[@]}" <<'PY'
import json, os, sys

def median_run(group):
    """The run with the median render time among comma-separated JSON files."""
    runs = sorted((json.load(open(p)) for p in group.split(",")), key=lambda j: j["render_seconds"])
    return runs[len(runs) // 2]

files = sys.argv[1:]
print("| scene | primitives | part 1 render s | part 2 render s | BVH build s | speed-up | Mrays/s (part 2) | tests/ray part 1 | tests/ray part 2 | nodes/ray part 2 |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for p1_path, p2_path in zip(files[0::2], files[1::2]):
    p1, p2 = median_run(p1_path), median_run(p2_path)
    speedup = p1["render_seconds"] / p2["render_seconds"] if p2["render_seconds"] > 0 else float("inf")
    print(f"| {os.path.basename(p1['scene'])} | {p1['primitives']} | {p1['render_seconds']:.3f} | {p2['render_seconds']:.4f} "
          f"| {p2['bvh_build_seconds']:.4f} | {speedup:.1f}x | {p2['mrays_per_second']:.2f} "
          f"| {p1['tests_per_ray']:.1f} | {p2['tests_per_ray']:.2f} | {p2['nodes_per_ray']:.2f} |")
PY
echo
echo "Render times exclude loading and the BVH build (shown separately); part 2: the run with the median"
echo "render time of $repeat. Commands (from $root; part 2 run $repeat times):"
echo
echo '```'
printf '%s\n' "${commands[@]}"
echo '```'
