#!/usr/bin/env bash
# The Cycles second opinion on every kind of surface and light the renderer
# has (README.md here): our scenes of parts 3-9, the course's 3-2 scenes
# when ../shared/cs184-scenes is there, and the microfacet box once more
# with F taken at wo (f_of_wo.patch, built in a temporary worktree), which
# is what Cycles can express.
#
#   instructors/cycles_check/run_all.sh [OUT.md] [FIGURES_DIR]
#   COURSE_DAE=DIR instructors/cycles_check/run_all.sh ...
#
# COURSE_DAE: the course starter repository's dae/sky folder (its 3-2
# scenes CBgems.dae, CBcoil.dae, CBbunny_microfacet_cu.dae and
# bunny_microfacet_cu_unlit.dae are compared too; they are the course's,
# read where they are, never copied here).
#
# Needs Blender (Debian's package blender) on PATH. About 10 minutes on two
# cores. Writes OUT.md (default instructors/cycles_check/results_runs.md)
# and one figure per comparison in FIGURES_DIR (default
# build/cycles_check/figures).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-$here/results_runs.md}
figs=${2:-$root/build/cycles_check/figures}
course=$root/../shared/cs184-scenes

# Debian's Python, with its numpy (python3-numpy), before any other on PATH.
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" -c "import numpy" 2>/dev/null || { echo "run_all.sh: $py has no numpy (apt install python3-numpy)" >&2; exit 1; }
command -v blender >/dev/null || { echo "run_all.sh: Blender is not on PATH (apt install blender)" >&2; exit 1; }
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j2 --target pathtracer scene_json >/dev/null
mkdir -p "$figs"

work=$(mktemp -d)
cleanup() {
  git -C "$root" worktree remove --force "$work/f_of_wo" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

{
  echo "# Cycles second opinion: runs"
  echo
  echo "Written by \`instructors/cycles_check/run_all.sh\` at commit $(git -C "$root" rev-parse --short HEAD),"
  echo "Blender $(blender -b --factory-startup -noaudio --python-expr 'import bpy; print("BV", bpy.app.version_string)' 2>/dev/null | sed -n 's/^BV //p')."
  echo "K = 8 renders each (ours at seeds 1000-1007, Cycles at 0-7), 8 x 6 blocks x 3 channels, Holm at alpha = 0.05."
} > "$out"

compare() {  # NAME TITLE SCENE FLAGS... [-- PATHTRACER]
  local name=$1 title=$2 scene=$3
  shift 3
  echo "run_all.sh: $name" >&2
  "$py" "$here/compare_cycles.py" --scene "$scene" "$@" -K 8 --figure "$figs/$name.png" \
    --markdown "$out" --title "$title" >/dev/null
}

s=$root/scenes
compare lambertian_m1 "Diffuse box, direct light only (part 3)" "$s/CBspheres_lambertian.dae" -s 64 -l 4 -m 1
compare lambertian_m5 "Diffuse box, five bounces (part 4)" "$s/CBspheres_lambertian.dae" -s 64 -l 4 -m 5
compare spheres_m5 "Mirror and glass box (part 6)" "$s/CBspheres.dae" -s 64 -l 4 -m 5
compare microfacet_m5 "Microfacet box, gold alpha 0.25 and copper alpha 0.05 (part 7)" \
  "$s/CBspheres_microfacet.dae" -s 64 -l 4 -m 5
compare envmap_m2 "Copper bunny under the sky map (part 8)" "$s/bunny_microfacet_envmap.dae" \
  -e "$s/sky_sun.exr" -s 64 -l 1 -m 2 -r 160 120
compare sun_diffuse_m2 "Diffuse bunny under the wide sun and an ambient light (part 8)" "$s/bunny_ambient.dae" \
  -e "$s/sky_wide_sun.exr" -s 64 -l 1 -m 2 -r 160 120
compare dof_m2 "Depth of field, -b 0.2 -d 4.1 (part 9)" "$s/CBspheres_dof.dae" -s 64 -l 1 -m 2 -b 0.2 -d 4.1

if [[ -d "$course" ]]; then
  compare course_spheres_m5 "The course's CBspheres.dae" "$course/CBspheres.dae" -s 64 -l 4 -m 5
  compare course_al_ag_m5 "The course's CBspheres_microfacet_al_ag.dae" "$course/CBspheres_microfacet_al_ag.dae" \
    -s 64 -l 4 -m 5
else
  echo -e "\nThe course's scenes were not compared: $course is not there." >> "$out"
fi

if [[ -n "${COURSE_DAE:-}" ]]; then
  compare course_gems_m5 "The course's CBgems.dae (glass gems)" "$COURSE_DAE/CBgems.dae" -s 64 -l 4 -m 5
  compare course_coil_m5 "The course's CBcoil.dae (a mirror coil)" "$COURSE_DAE/CBcoil.dae" -s 64 -l 4 -m 5
  compare course_cu_bunny_m5 "The course's CBbunny_microfacet_cu.dae" "$COURSE_DAE/CBbunny_microfacet_cu.dae" \
    -s 64 -l 4 -m 5
  compare course_cu_bunny_unlit_m2 "The course's bunny_microfacet_cu_unlit.dae under our sky map" \
    "$COURSE_DAE/bunny_microfacet_cu_unlit.dae" -e "$s/sky_sun.exr" -s 64 -l 1 -m 2 -r 160 120
fi

# The microfacet box again with F at wo: Cycles fixes a closure's colour
# before it picks a light, so it can only take F at the outgoing direction.
echo "run_all.sh: building the F(wo) variant" >&2
git -C "$root" worktree add --detach "$work/f_of_wo" HEAD >/dev/null 2>&1
git -C "$work/f_of_wo" apply "$here/f_of_wo.patch"
cmake -S "$work/f_of_wo" -B "$work/f_of_wo/build" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF >/dev/null
cmake --build "$work/f_of_wo/build" -j2 --target pathtracer >/dev/null
compare microfacet_m5_f_of_wo "Microfacet box, ours with F at wo (f_of_wo.patch)" "$s/CBspheres_microfacet.dae" \
  -s 64 -l 4 -m 5 --pathtracer "$work/f_of_wo/build/bin/pathtracer"
compare envmap_m1_f_of_wo "Copper bunny under the sky map, direct light only, ours with F at wo" \
  "$s/bunny_microfacet_envmap.dae" -e "$s/sky_sun.exr" -s 256 -l 1 -m 1 -r 160 120 \
  --pathtracer "$work/f_of_wo/build/bin/pathtracer"
if [[ -d "$course" ]]; then
  compare course_al_ag_m5_f_of_wo "The course's CBspheres_microfacet_al_ag.dae, ours with F at wo" \
    "$course/CBspheres_microfacet_al_ag.dae" -s 64 -l 4 -m 5 --pathtracer "$work/f_of_wo/build/bin/pathtracer"
fi
if [[ -n "${COURSE_DAE:-}" ]]; then
  compare course_cu_bunny_m5_f_of_wo "The course's CBbunny_microfacet_cu.dae, ours with F at wo" \
    "$COURSE_DAE/CBbunny_microfacet_cu.dae" -s 64 -l 4 -m 5 --pathtracer "$work/f_of_wo/build/bin/pathtracer"
fi
echo "run_all.sh: wrote $out and $figs/" >&2
