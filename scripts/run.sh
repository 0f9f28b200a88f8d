#!/usr/bin/env bash
# The main job: install what is missing, build the renderer and render the
# default scene, then build the grader and grade the reference build on
# every case (only those two targets: scripts/test.sh builds the rest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --build-only
scripts/build.sh pathtracer
mkdir -p out
threads=$(nproc 2>/dev/null || echo 2)
# The course's standard command: global illumination, adaptive sampling.
build/bin/pathtracer -t "$threads" -s 64 -l 4 -m 5 -r 480 360 -f out/CBspheres_lambertian.png \
  scenes/CBspheres_lambertian.dae
echo
echo "Rendered: $(pwd)/out/CBspheres_lambertian.png (sample rates: out/CBspheres_lambertian_rate.png)"
echo
echo "Building the grader ..."
scripts/build.sh grader
echo "Grading the reference build (build/bin/pathtracer) on every case:"
build/bin/grader run -q -j "$threads" -o out/grade
