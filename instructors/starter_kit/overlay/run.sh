#!/usr/bin/env bash
# Install what is missing, build the renderer (only it: scripts/check.sh N
# builds part N's tests, scripts/build.sh everything), render the scene of
# the first part you write with your build, list what is not implemented
# yet, then build the grader and grade your build on every case.
# Arguments go to the grader, e.g. `scripts/run.sh --part 1` grades only
# part 1's cases. Exit status: the grader's (0 when every case passed).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --build-only
scripts/build.sh pathtracer
mkdir -p out
threads=$(nproc 2>/dev/null || echo 2)

# The parts this kit gives solved (solved_parts.txt, one number a line). A
# kit that gives parts 1-5 (Project 3-1) starts on Project 3-2: the course's
# mirror and glass scene, and a small render that reaches parts 7-9
# (microfacet spheres, an environment map, a thin lens) to list their
# functions too.
solved=$(grep -E '^[0-9]+$' solved_parts.txt 2>/dev/null | tr '\n' ' ' || true)
starts_on_3_2=1
for part in 1 2 3 4 5; do
  [[ " $solved " == *" $part "* ]] || starts_on_3_2=0
done
if [ "$starts_on_3_2" = 1 ]; then
  scene=CBspheres
else
  scene=CBspheres_lambertian
fi
image=out/$scene.png
log=out/$scene.stderr.txt

# The course's standard command: global illumination, adaptive sampling.
echo "Rendering scenes/$scene.dae with your build:"
if build/bin/pathtracer -t "$threads" -s 64 -l 4 -m 5 -r 480 360 -f "$image" \
     "scenes/$scene.dae" 2>"$log"; then
  grep -v "^TODO: implement " "$log" >&2 || true
  echo
  echo "Rendered with your build: $image (sample rates: ${image%.png}_rate.png)"
else
  status=$?
  grep -v "^TODO: implement " "$log" >&2 || true
  echo
  echo "The render failed with exit status $status (its messages are above)."
fi
todo_logs=("$log")
if [ "$starts_on_3_2" = 1 ]; then
  probe_log=out/todo_probe.stderr.txt
  build/bin/pathtracer -t "$threads" -s 1 -l 1 -m 2 -r 480 360 -e scenes/sky_sun.exr -b 0.1 \
    -f out/todo_probe.png scenes/CBspheres_microfacet.dae >/dev/null 2>"$probe_log" || true
  rm -f out/todo_probe.png out/todo_probe_rate.png  # only its TODO lines are wanted
  todo_logs+=("$probe_log")
fi
# What is still a stub, part by part (in the order the renders met them).
sed -n 's/^TODO: implement /Not implemented yet: /p' "${todo_logs[@]}" | awk '!seen[$0]++' | sort -s -k5,5n

echo
echo "Building the grader ..."
scripts/build.sh grader
if [ $# -eq 0 ]; then
  echo "Grading your build (build/bin/pathtracer) on every case:"
else
  echo "Grading your build (build/bin/pathtracer), grader run $*:"
fi
grade_status=0
build/bin/grader run -q -j "$threads" -o out/grade "$@" || grade_status=$?
echo
if [ -s out/grade/report.html ]; then
  echo "Your report: out/grade/report.html (open it in a browser; the table is in out/grade/report.txt)"
else
  echo "The grader wrote no report (exit status $grade_status): see its message above."
fi
exit "$grade_status"
