#!/usr/bin/env bash
# Install what is missing, build the renderer and the grader (only those:
# scripts/test.sh builds the tests, scripts/build.sh everything), render the
# default scene with your build, list what is not implemented yet, then
# grade your build on every case.
# Arguments go to the grader, e.g. `scripts/run.sh --part 1` grades only
# part 1's cases. Exit status: the grader's (0 when every case passed).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --build-only
scripts/build.sh pathtracer grader
mkdir -p out
threads=$(nproc 2>/dev/null || echo 2)
image=out/CBspheres_lambertian.png
log=out/CBspheres_lambertian.stderr.txt

# The course's standard command: global illumination, adaptive sampling.
echo "Rendering scenes/CBspheres_lambertian.dae with your build:"
if build/bin/pathtracer -t "$threads" -s 64 -l 4 -m 5 -r 480 360 -f "$image" \
     scenes/CBspheres_lambertian.dae 2>"$log"; then
  grep -v "^TODO: implement " "$log" >&2 || true
  echo
  echo "Rendered with your build: $image (sample rates: ${image%.png}_rate.png)"
else
  status=$?
  grep -v "^TODO: implement " "$log" >&2 || true
  echo
  echo "The render failed with exit status $status (its messages are above)."
fi
# What is still a stub, part by part (in the order the render met them).
sed -n 's/^TODO: implement /Not implemented yet: /p' "$log" | sort -s -k5,5n

echo
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
