#!/usr/bin/env bash
# Does a Cornell box of mirror and glass, or of microfacet metal, render at
# no fewer million rays per second than the diffuse one? The three boxes
# differ only in their spheres' materials (scenes/CBspheres_lambertian.dae,
# CBspheres.dae, CBspheres_microfacet.dae).
#
#   instructors/bench/material_speed.sh [REPS] [PATHTRACER]
#
# Renders each scene REPS times (default 5), the three interleaved so that
# the machine's load falls on all of them alike, with the same settings
# (--part 9 -t 1 -s 32 -l 4 -m 5 -r 320 240, a different --seed per
# repetition), and prints a Markdown table of medians: each scene's rays,
# its Mrays/s as the console line counts it (rays / render seconds, wall
# clock), its Mrays per CPU second (rays / the process's user and system
# time less loading and the BVH build: what another process's load does
# not change), and both against the diffuse box. Progress goes to stderr.
# Builds build/bin/pathtracer first unless PATHTRACER is given.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
reps=${1:-5}
pt=${2:-}
if [[ -z "$pt" ]]; then
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$root/build" -j2 --target pathtracer >/dev/null
  pt="$root/build/bin/pathtracer"
fi

python3 - "$pt" "$root/scenes" "$reps" <<'PY'
import json, os, resource, statistics, subprocess, sys, tempfile
pt, scenes_dir, reps = sys.argv[1], sys.argv[2], int(sys.argv[3])
scenes = ["CBspheres_lambertian.dae", "CBspheres.dae", "CBspheres_microfacet.dae"]
settings = ["--part", "9", "-t", "1", "-s", "32", "-l", "4", "-m", "5", "-r", "320", "240"]
runs = {s: [] for s in scenes}
with tempfile.TemporaryDirectory() as work:
    for r in range(reps):
        for s in scenes:
            print(f"material_speed.sh: {s}, repetition {r + 1} of {reps}", file=sys.stderr)
            stats = os.path.join(work, "stats.json")
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([pt, *settings, "--seed", str(r), "--no-progress", "-f", os.path.join(work, "out.png"),
                            "--stats-json", stats, os.path.join(scenes_dir, s)], stdout=subprocess.DEVNULL, check=True)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            j = json.load(open(stats))
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            cpu -= j["load_seconds"] + j["bvh_build_seconds"]
            runs[s].append((j["rays"], j["rays"] / j["render_seconds"] * 1e-6, j["rays"] / cpu * 1e-6))
med = {s: [statistics.median(x[i] for x in runs[s]) for i in range(3)] for s in scenes}
base = med[scenes[0]]
print(f"Same settings: {' '.join(settings)}, {reps} repetitions each, interleaved; medians.\n")
print("| scene | rays | Mrays/s (wall) | against diffuse | Mrays per CPU second | against diffuse |")
print("|---|---:|---:|---:|---:|---:|")
for s in scenes:
    rays, wall, cpu = med[s]
    print(f"| `{s}` | {rays:,.0f} | {wall:.3f} | {wall / base[1]:.2f}x | {cpu:.3f} | {cpu / base[2]:.3f}x |")
PY
