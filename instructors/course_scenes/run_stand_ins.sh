#!/bin/sh
# Writes staff_comparison.md's measured part: compare_staff.py with our own
# render at another seed standing in for the staff image (no staff image of
# 3-2 with known settings can be read here; see README.md). Four runs, about
# four minutes on one core: the test's false alarms on the two 3-2 scenes
# (A, B), and what it sees when the stand-in differs from our settings as a
# staff image of unknown settings might: 16 instead of 64 samples per pixel
# (C), depth 5 instead of 7 (D).
#   instructors/course_scenes/run_stand_ins.sh [SCENES_DIR] [OUT.md]
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
scenes=${1:-$root/../shared/cs184-scenes}
out=${2:-$root/instructors/course_scenes/staff_comparison_runs.md}
figs=$root/instructors/course_scenes/figures
py=/usr/bin/python3
[ -x "$py" ] || py=python3
for f in CBspheres.dae CBspheres_microfacet_al_ag.dae; do
  [ -f "$scenes/$f" ] || { echo "run_stand_ins.sh: error: $scenes/$f: the course's scene is missing" >&2; exit 1; }
done
[ -x "$root/build/bin/pathtracer" ] || { echo "run_stand_ins.sh: error: build/bin/pathtracer: build it first" >&2; exit 1; }
mkdir -p "$figs"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
{
  echo "## Stand-in runs (made by run_stand_ins.sh at commit $(git -C "$root" rev-parse --short HEAD), $(date -u +%Y-%m-%d))"
  echo
} > "$tmp"
common="-s 64 -l 4 -m 7 -r 480 360 -K 8 --grid 8 6 --alpha 0.05 --markdown $tmp"
run() { # name scene pseudo-args title
  $py "$root/instructors/course_scenes/compare_staff.py" --scene "$scenes/$2" --pseudo-staff 1 \
    --pseudo-staff-args="$3" $common --figure "$figs/$1.png" --title "$4" >/dev/null
}
run A_spheres_null CBspheres.dae "" "A. CBspheres.dae, stand-in with our settings (no difference: false alarms)"
run B_microfacet_null CBspheres_microfacet_al_ag.dae "" "B. CBspheres_microfacet_al_ag.dae, stand-in with our settings (no difference: false alarms)"
run C_spheres_s16 CBspheres.dae "-s 16" "C. CBspheres.dae, stand-in at -s 16 against ours at -s 64 (unknown sample count)"
run D_microfacet_m5 CBspheres_microfacet_al_ag.dae "-m 5" "D. CBspheres_microfacet_al_ag.dae, stand-in at -m 5 against ours at -m 7 (wrongly inferred depth)"
mv "$tmp" "$out"
trap - EXIT
echo "run_stand_ins.sh: wrote $out and $figs/"
