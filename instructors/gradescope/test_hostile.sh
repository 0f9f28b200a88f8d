#!/usr/bin/env bash
# Hostile submissions through the real package: make_autograder.sh, then
# setup.sh, then run_autograder, as Gradescope runs them (as root, with
# AUTOGRADER_ROOT under /tmp and AUTOGRADER_SKIP_APT=1). Each submission is
# the reference's stages/ with the camera upside down (the base: it cannot
# get its points by rendering) plus one trick; each must gain no point by
# its trick, leave the autograder unchanged (setup.sh's hashes, checked here
# again) and leak nothing into results.json (canary strings put in the case
# lists and the references' folder), and leave no process behind.
#
#   instructors/gradescope/test_hostile.sh --pathtracer P --grader G [--work WORK] [--step STEP]...
#   instructors/gradescope/test_hostile.sh --pathtracer P --grader G --package TREE --report FILE
#
# Steps (without --step: all, in this order):
#   prepare   a hidden case and its reference (made with P and G), the zip
#             (make_autograder.sh, HIDDEN_CASES=), unpacked; canaries; setup.sh
#   control   the reference's stages/: full marks on every case (hidden too)
#   base      the base (upside down): its scores, which the tricks must not beat
#   a         at exit, the reference found through the parent's --references,
#             the output folder's parents or a search of /, written as the render
#   b         CMake code (stages/CMakeLists.txt, a part's CMakeLists.txt, a
#             .cmake) that replaces the grader with one giving full marks, and
#             a shell script beside it
#   c         #include of files outside the submission: ../../grader/cases.txt,
#             the zip's case list by its absolute path, a reference's meta.json
#   d         a link in a part folder to the case list, #included
#   e         at exit, writes outside its case folder: results.json files,
#             other cases' outputs, the references, the grader's binary
#   f         at exit, a daemon that keeps writing full marks into results.json
#   g         at exit, a connection to a port this test listens on (loopback)
#   h         the kit's own p1_teapot reference shipped in the submission and
#             replayed at exit: it gains p1_teapot's point (a public case
#             cannot defeat it) and nothing on the hidden case
#   i         in the function checks (pathtracer --probe, which the grader
#             runs once when a build loses points), at exit: what it can
#             read of the references written into the checks' file as its
#             own words, and a daemon that keeps writing full marks into
#             results.json
#
# Graded cases: p1_teapot and p1_empty (public) and one hidden case, h1_cow.
# --package TREE: the package of another checkout (e.g. main before this
# sandbox), no assertions: each submission's score and what it did go to
# FILE (the README's before/after table); the autograder is restored from a
# copy before each submission, since an old package may be changed by one.
# Needs root (accounts, chown); exits 77 (skipped) saying so otherwise.
# KEEP_TMP=1 keeps the AUTOGRADER_ROOT in /tmp.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
. "$root/tests/timeout_scale/timeout_scale.sh"
public_cases=(p1_teapot p1_empty)
hidden_case=h1_cow
all_steps=(prepare control base a b c d e f g h i)

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; exit 2; }
ref_pathtracer="" ref_grader="" work="" package_tree="" report="" steps=()
while [ $# -gt 0 ]; do
  case "$1" in
    --pathtracer) ref_pathtracer=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --grader) ref_grader=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --work) work=$2; shift 2 ;;
    --step) steps+=("$2"); shift 2 ;;
    --package) package_tree=$(cd "$2" && pwd); shift 2 ;;
    --report) report=$2; shift 2 ;;
    -h | --help) usage ;;
    *) usage ;;
  esac
done
[ -n "$ref_pathtracer" ] && [ -n "$ref_grader" ] || usage
given_steps=${#steps[@]}
[ ${#steps[@]} -gt 0 ] || steps=("${all_steps[@]}")
if [ "$(id -u)" != 0 ]; then
  echo "test_hostile: SKIPPED: needs root (setup.sh makes the sandbox accounts, run_autograder switches to them)"
  exit 77
fi
command -v bwrap >/dev/null || echo "test_hostile: note: no bwrap: the sandbox is user mode (accounts alone)"
if [ -n "$package_tree" ]; then
  [ -n "$report" ] || usage
  report=$(cd "$(dirname "$report")" && pwd)/$(basename "$report")
fi
if [ -z "$work" ]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/gradescope-hostile.XXXXXX")
  [ "${KEEP_TMP:-0}" = 1 ] || trap 'rm -rf "$work" "$agbase"' EXIT
fi
mkdir -p "$work"
work=$(cd "$work" && pwd)
# The hidden cases made here are an instructor's private copy: in user mode
# the accounts see every file others may read, and the grader refuses to
# grade while a copy of a hidden case's file is readable.
chmod 0700 "$work"
# The AUTOGRADER_ROOT, under /tmp whatever WORK is: the accounts must pass
# through every folder above it.
agbase=/tmp/pt-hostile-$(printf '%s' "$work" | sha1sum | cut -c1-10)
ag=$agbase/ag
canary=CANARY-$(printf '%s' "$work" | sha1sum | cut -c11-22)

failures=0
. "$root/tests/shell/check.sh"  # check DESCRIPTION COMMAND...
need() { [ -e "$1" ] || { echo "FAILED: no $1: run the $2 step first" >&2; exit 1; }; }

# ---- prepare ----
step_prepare() {
  rm -rf "$agbase" "$work/hidden" "$work/reference_work" "$work/runs" "$work/scores"
  mkdir -p "$agbase" "$work/scores"
  chmod 0711 "$agbase"
  # A hidden case: the cow at a size no public case has (the public
  # references are of no use for it), which an upside-down camera fails.
  mkdir -p "$work/hidden"
  printf '# Hidden cases of the hostile-submission test (%s)\n%-12s 1 image 1 60 cow.dae -r 80 60\n' \
    "$canary" "$hidden_case" >"$work/hidden/cases.txt"
  "$ref_grader" make-references --pathtracer "$ref_pathtracer" --runs 2 --case "$hidden_case" \
    --cases "$work/hidden/cases.txt" --scenes "$root/scenes" --references "$work/hidden/references" \
    --work "$work/reference_work" -j 2 --timeout-scale "$(timeout_scale)" >"$work/hidden_reference.log" 2>&1 || {
    tail -20 "$work/hidden_reference.log"
    echo "FAILED: making the hidden case's reference"
    exit 1
  }
  local pkg=${package_tree:-$root}
  HIDDEN_CASES=$work/hidden ALLOW_MISSING_REFERENCES=1 "$pkg/instructors/gradescope/make_autograder.sh" \
    --unpacked "$ag/source" >"$work/zip.log" 2>&1 || { cat "$work/zip.log"; echo "FAILED: make_autograder.sh"; exit 1; }
  # This autograder's starter code is the reference's own stages/, not the
  # stubbed kit's: every submission below is the reference with a change or
  # two, so that each run recompiles only the files it changes (the suite's
  # time). The intake's rules against a stubbed kit are tested by
  # test_submission_tools.py and test_package.sh.
  if [ -z "$package_tree" ]; then
    rm -rf "$ag/source/project/stages"
    cp -R "$root/stages" "$ag/source/project/stages"
  fi
  # Canaries in what must never reach a student.
  # (first and last: a feedback cut after its first errors still shows the first)
  sed -i "1i # $canary" "$ag/source/project/grader/cases.txt"
  echo "# $canary" >>"$ag/source/project/grader/cases.txt"
  echo "$canary" >>"$ag/source/project/reference_images/README.md"
  (cd "$ag/source" && AUTOGRADER_ROOT=$ag AUTOGRADER_SKIP_APT=1 AUTOGRADER_RENDER_ACCOUNTS=2 bash ./setup.sh) \
    >"$work/setup.log" 2>&1 || { tail -40 "$work/setup.log"; echo "FAILED: setup.sh"; exit 1; }
  cp "$ag/source/run_autograder" "$ag/run_autograder"
  if [ -n "$package_tree" ]; then
    rm -rf "$agbase/pristine"
    cp -a "$ag" "$agbase/pristine"
  fi
  echo "ok: the zip is made and set up in $ag"
}

# ---- submissions ----
# base_submission NAME [reference]: the reference's stages/ in a kit folder,
# upside down unless "reference".
base_submission() {
  local sub=$work/runs/$1/submission
  rm -rf "$work/runs/$1"
  mkdir -p "$sub/pathtracer-kit"
  cp -R "$root/stages" "$sub/pathtracer-kit/stages"
  if [ "${2:-}" != reference ]; then
    patch -s -d "$sub/pathtracer-kit" -p1 <"$root/instructors/mutants/patches/camera_y_flipped.patch"
  fi
  echo "$sub/pathtracer-kit/stages"
}
append_trick() {  # append_trick STAGES FILE.inc...: appended to part 1's pixel_sampling.cpp
  local stages=$1
  shift
  cat "$here/hostile/prelude.inc" "$@" >>"$stages/part1_raytracing/pixel_sampling.cpp"
}

# grade NAME: run_autograder on $work/runs/NAME/submission as Gradescope
# runs it; results.json in $work/runs/NAME/results.json.
grade() {
  local name=$1 rc=0 dir=$work/runs/$1
  need "$ag/run_autograder" prepare
  if [ -n "$package_tree" ]; then
    rm -rf "$ag"
    cp -a "$agbase/pristine" "$ag"
  fi
  rm -rf "$ag/results"
  local args="--timeout-scale $(timeout_scale)"
  for c in "${public_cases[@]}"; do args+=" --case $c"; done
  # An old package (--package) may have no hidden cases.
  [ -f "$ag/source/hidden/cases.txt" ] && args+=" --case $hidden_case"
  (cd "$ag" && AUTOGRADER_ROOT=$ag AUTOGRADER_SUBMISSION=$dir/submission GRADER_JOBS=2 \
    BUILD_TIMEOUT=$(scaled_seconds 1200) GRADER_ARGS="$args" ./run_autograder) >"$dir/log.txt" 2>&1 || rc=$?
  cp "$ag/results/results.json" "$dir/results.json" 2>/dev/null || true
  echo "$rc" >"$dir/rc"
}

# scores FILE: "total public hidden" of a results.json (hidden: the tests
# whose name holds no public case's name).
scores() {
  python3 - "$1" "${public_cases[@]}" <<'EOF'
import json, sys
try:
    d = json.load(open(sys.argv[1]))
except (OSError, ValueError):
    print("nan nan nan")
    sys.exit(0)
public = sys.argv[2:]
pub = sum(t.get("score", 0) for t in d.get("tests", []) if any(c in t.get("name", "") for c in public))
total = float(d.get("score", 0))
print(f"{total:g} {pub:g} {total - pub:g}")
EOF
}

# The checks every hostile run must pass.
common_checks() {
  local name=$1 dir=$work/runs/$1
  check "$name: run_autograder exits 0" test "$(cat "$dir/rc")" = 0
  check "$name: results.json is valid, with the output hidden from students" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
float(d["score"])
sys.exit(0 if d.get("stdout_visibility") == "hidden" else 1)' "$dir/results.json"
  check "$name: results.json holds no canary and no path of the zip" \
    bash -c '! grep -q -e "$1" -e "$2" -e "$3" "$4"' _ "$canary" "$ag/source" "/autograder/source" "$dir/results.json"
  local now
  now=$(mapfile -t p <"$ag/pt/manifest_paths.txt"; python3 "$ag/source/submission_tools.py" manifest "${p[@]}")
  check "$name: the autograder is unchanged (setup.sh's hashes)" test "$now" = "$(cat "$ag/pt/manifest.txt")"
  check "$name: no process of the sandbox accounts is left" bash -c '
    for a in pt-build pt-render1 pt-render2; do
      u=$(id -u "$a") || exit 1
      left=$(awk -v u="$u" "/^Uid:/ { if (\$2 == u || \$3 == u) print FILENAME }" /proc/[0-9]*/status 2>/dev/null || true)
      [ -z "$left" ] || { echo "  left: $a: $left"; exit 1; }
    done
    ! grep -qx hostile-daemon /proc/[0-9]*/comm 2>/dev/null'
  check "$name: run_autograder says it ran in a sandbox" grep -q "^== Sandbox: \(bwrap\|user\)" "$dir/log.txt"
}
no_gain() {  # no_gain NAME: its score is at most the base's
  local name=$1 s b
  s=$(scores "$work/runs/$name/results.json")
  b=$(cat "$work/scores/base")
  echo "  $name: score ${s%% *} (base ${b%% *})"
  check "$name: gains nothing by its trick (score ${s%% *} <= the base's ${b%% *})" \
    python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) <= float(sys.argv[2]) else 1)' "${s%% *}" "${b%% *}"
}

step_control() {
  base_submission control reference >/dev/null
  grade control
  common_checks control
  check "control: full marks on the public cases and the hidden one" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
tests = [t for t in d.get("tests", []) if t.get("max_score") is not None]  # not the staff-only lines
full = sum(t["max_score"] for t in tests)
score = d["score"]
print(f"  control: {score:g} of {full:g} in {len(tests)} tests")
sys.exit(0 if len(tests) == 3 and full > 0 and abs(d["score"] - full) < 1e-9 else 1)' "$work/runs/control/results.json"
}

step_base() {
  base_submission base >/dev/null
  grade base
  common_checks base
  scores "$work/runs/base/results.json" >"$work/scores/base"
  check "base: graded (3 tests)" python3 -c '
import json, sys
sys.exit(0 if len([t for t in json.load(open(sys.argv[1])).get("tests", []) if t.get("max_score") is not None]) == 3 else 1)' "$work/runs/base/results.json"
  echo "  base: scores (total public hidden) $(cat "$work/scores/base")"
}

step_a() {
  append_trick "$(base_submission a)" "$here/hostile/a_read_references.inc"
  grade a
  common_checks a
  if grep -q "^== Sandbox: user" "$work/runs/a/log.txt"; then
    # In user mode the accounts may read any copy of the public references
    # the machine lets others read (here this checkout's; on Gradescope the
    # submission's own, as in h): what no sandbox can keep from a student.
    # The hidden case is what must stay out of reach.
    local s b
    s=$(scores "$work/runs/a/results.json")
    b=$(cat "$work/scores/base")
    echo "  a (user mode): score ${s%% *} (public $(echo "$s" | cut -d' ' -f2), hidden ${s##* }); base ${b%% *}"
    check "a: gains nothing on the hidden case (${s##* } <= the base's ${b##* })" \
      python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) <= float(sys.argv[2]) else 1)' "${s##* }" "${b##* }"
  else
    no_gain a
  fi
}

step_b() {
  local stages marker=$agbase/hostile-b-ran
  stages=$(base_submission b)
  rm -f "$marker"
  # Configure-time code, as a student would write it: replace the grader
  # (wherever it may be) with a script giving 100, and leave a marker.
  local payload
  payload=$(cat <<EOF
file(WRITE "$marker" "configure-time code ran\n")
foreach(g "\${CMAKE_SOURCE_DIR}/../bin/grader" "\${CMAKE_SOURCE_DIR}/../../pt/bin/grader" "$ag/pt/bin/grader")
  file(WRITE "\${g}" "#!/bin/sh\nfor a; do case \$prev in -o) mkdir -p \$a; printf '{\"score\": 100, \"output\": \"hostile b\"}' >\$a/results.json;; esac; prev=\$a; done\n")
  execute_process(COMMAND chmod 755 "\${g}")
endforeach()
EOF
  )
  printf '\n%s\n' "$payload" >>"$stages/CMakeLists.txt"
  printf '\n%s\n' "$payload" >>"$stages/part1_raytracing/CMakeLists.txt"
  printf '%s\n' "$payload" >"$stages/part1_raytracing/hostile.cmake"
  printf 'include(${CMAKE_CURRENT_LIST_DIR}/../part1_raytracing/hostile.cmake)\n' >>"$stages/part2_bvh/CMakeLists.txt"
  printf '#!/bin/sh\ntouch "%s"\n' "$marker" >"$stages/part1_raytracing/build.sh"
  chmod +x "$stages/part1_raytracing/build.sh"
  grade b
  common_checks b
  no_gain b
  check "b: no configure-time code ran (no marker)" test ! -e "$marker"
  check "b: the feedback lists the ignored build files on one line" grep -q "Ignored from your stages/: .*build files" \
    "$work/runs/b/results.json"
}

step_c() {
  local stages
  stages=$(base_submission c)
  # Three includes of files outside the submission, each in a header of its
  # own, all included by sphere.cpp.
  printf '#include "../../grader/cases.txt"\n' >"$stages/part1_raytracing/leak_relative.h"
  printf '#include "%s"\n' "$ag/source/project/grader/cases.txt" >"$stages/part1_raytracing/leak_absolute.h"
  printf '#include "../../reference_images/README.md"\n#include "/autograder/source/project/grader/cases.txt"\n' \
    >"$stages/part1_raytracing/leak_reference.h"
  sed -i '1i #include "leak_relative.h"\n#include "leak_absolute.h"\n#include "leak_reference.h"' \
    "$stages/part1_raytracing/sphere.cpp"
  grade c
  common_checks c
  no_gain c
  check "c: the build failed on the missing files, saying so" grep -q "No such file or directory" "$work/runs/c/results.json"
}

step_d() {
  local stages
  stages=$(base_submission d)
  ln -s "$ag/source/project/grader/cases.txt" "$stages/part1_raytracing/cases_link.h"
  ln -s ../../reference_images "$stages/part1_raytracing/refs"
  sed -i '1i #include "cases_link.h"' "$stages/part1_raytracing/sphere.cpp"
  grade d
  common_checks d
  no_gain d
  check "d: the feedback says the links were ignored" grep -q "Ignored from your stages/: .*links" \
    "$work/runs/d/results.json"
}

step_e() {
  append_trick "$(base_submission e)" "$here/hostile/e_write_outside.inc"
  grade e
  common_checks e
  no_gain e
}

step_f() {
  append_trick "$(base_submission f)" "$here/hostile/f_daemon.inc"
  grade f
  common_checks f
  no_gain f
  # The daemon had ten minutes to live: killed, results.json is the grader's.
  check "f: results.json is the grader's (3 tests)" python3 -c '
import json, sys
sys.exit(0 if len([t for t in json.load(open(sys.argv[1])).get("tests", []) if t.get("max_score") is not None]) == 3 else 1)' "$ag/results/results.json"
}

step_i() {
  append_trick "$(base_submission i)" "$here/hostile/i_probe.inc"
  grade i
  common_checks i
  no_gain i
  local out=$ag/results/grader_out
  # The trick ran where it meant to: in the function checks, at their exit.
  check "i: its trick ran in the function checks" grep -q "^hostile: read" "$out/probes/stderr.txt"
  check "i: results.json is the grader's (3 tests)" python3 -c '
import json, sys
sys.exit(0 if len([t for t in json.load(open(sys.argv[1])).get("tests", []) if t.get("max_score") is not None]) == 3 else 1)' "$ag/results/results.json"
  # Its file is read as its answers, and only the grader's words are quoted.
  check "i: the report says, in the grader's words, that generate_ray's checks did not finish" \
    grep -q "generate_ray (part 1) answers differently from the reference's: did not finish its checks\|generate_ray answers the grader's function checks differently from the reference's (did not finish its checks)" \
    "$out/report.txt"
  check "i: none of the checks' file's own words reach results.json" \
    bash -c '! grep -q -e "nothing readable" -e "hostile" -e "1e30" -e "1e+30" "$1"' _ "$work/runs/i/results.json"
}

step_g() {
  local stages port listener got=$work/runs/g-received
  stages=$(base_submission g)
  rm -f "$got"
  # A listener on loopback, on a free port, that writes whatever it gets.
  exec {portfd}< <(python3 - "$got" <<'EOF'

import socket, sys
s = socket.socket()
s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("127.0.0.1", 0))
s.listen(8)
print(s.getsockname()[1], flush=True)
s.settimeout(900)
with open(sys.argv[1], "ab") as out:
    while True:
        try:
            c, _ = s.accept()
        except OSError:
            break
        c.settimeout(5)
        try:
            out.write(c.recv(4096) or b"(connected)\n")
        except OSError:
            out.write(b"(connected)\n")
        out.flush()
        c.close()
EOF
  )
  listener=$!
  read -r port <&"$portfd"
  sed "s/@PORT@/$port/" "$here/hostile/g_network.inc" >"$work/runs/g.inc"
  append_trick "$stages" "$work/runs/g.inc"
  grade g
  # Nothing connected: the listener's file is empty or absent.
  kill "$listener" 2>/dev/null || true
  wait "$listener" 2>/dev/null || true
  exec {portfd}<&-
  common_checks g
  no_gain g
  check "g: no connection reached the port on loopback" test ! -s "$got"
}

step_h() {
  local stages b s
  stages=$(base_submission h)
  python3 - "$root/reference_images" "$stages/part1_raytracing/replay_data.h" p1_teapot <<'EOF'
import json, re, sys
refs, out, cases = sys.argv[1], sys.argv[2], sys.argv[3:]
lines = ["// The kit's own references (reference_images/), as bytes.", "#pragma once", "#include <cstddef>",
         "struct ReplayEntry { const char* scene; int w, h; const unsigned char* bytes; std::size_t size; };"]
entries = []
for i, c in enumerate(cases):
    meta = json.load(open(f"{refs}/{c}/meta.json"))
    m = re.search(r"-r (\d+) (\d+)", meta["command"])
    scene = next(w for w in meta["command"].split() if w.endswith(".dae"))
    data = open(f"{refs}/{c}/mean.pfm", "rb").read()
    lines.append(f"static const unsigned char kBytes{i}[] = {{" + ",".join(str(b) for b in data) + "};")
    entries.append(f'{{"{scene}", {m.group(1)}, {m.group(2)}, kBytes{i}, sizeof kBytes{i}}}')
lines.append("static const ReplayEntry kReplay[] = {" + ", ".join(entries) + "};")
open(out, "w").write("\n".join(lines) + "\n")
EOF
  append_trick "$stages" "$here/hostile/h_replay.inc"
  grade h
  common_checks h
  s=$(scores "$work/runs/h/results.json")
  b=$(cat "$work/scores/base")
  read -r st sp sh <<<"$s"
  read -r bt bp bh <<<"$b"
  echo "  h: score $st (public $sp, hidden $sh); base $bt (public $bp, hidden $bh); gain on public cases: $(python3 -c "print(f'{$sp - $bp:g}')")"
  echo "$s" >"$work/scores/h"
  check "h: gains nothing on the hidden case ($sh <= the base's $bh)" \
    python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) <= float(sys.argv[2]) else 1)' "$sh" "$bh"
  # The trick is live: replay_data.h was taken, and the replay gains on p1_teapot.
  check "h: replay_data.h was taken (not listed as ignored)" bash -c '! grep -q replay_data.h "$1"' _ "$work/runs/h/results.json"
  check "h: the replay gains on the public case it carries ($sp > the base's $bp)" \
    python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) > float(sys.argv[2]) else 1)' "$sp" "$bp"
}

# ---- --package TREE: scores only, for the before/after table ----
report_run() {
  local name=$1 dir=$work/runs/$1 s leak=no changed=no left=no
  s=$(scores "$dir/results.json")
  grep -q -e "$canary" "$dir/results.json" 2>/dev/null && leak=yes
  [ "$name" = b ] && [ -e "$agbase/hostile-b-ran" ] && changed="yes (configure-time code ran)"
  grep -qx hostile-daemon /proc/[0-9]*/comm 2>/dev/null && left=yes
  echo "$name ${s// /,} leak=$leak changed=$changed daemon=$left rc=$(cat "$dir/rc")" >>"$report"
  echo "report: $name: total,public,hidden=${s// /,} leak=$leak $changed daemon=$left"
  # A daemon of an old package runs as root: end it by its pid.
  local p
  for p in $(grep -lx hostile-daemon /proc/[0-9]*/comm 2>/dev/null | cut -d/ -f3); do kill -KILL "$p" 2>/dev/null || true; done
}

if [ -n "$package_tree" ]; then
  [ "$given_steps" -gt 0 ] || : >"$report"
  # The same submissions as the steps, graded without the checks.
  check() { :; }
  no_gain() { :; }
  common_checks() { :; }
  # --step S...: only those submissions, in the autograder a run kept
  # (KEEP_TMP=1) set up; the base's scores from that run.
  if [ "$given_steps" -gt 0 ] && [ "${steps[0]}" != prepare ] && [ -d "$agbase/pristine" ]; then
    todo=("${steps[@]}")
  else
    step_prepare
    todo=(control base a b c d e f g h i)
  fi
  for s in "${todo[@]}"; do
    "step_$s" || true
    report_run "$s"
  done
  [ "${KEEP_TMP:-0}" = 1 ] || rm -rf "$agbase"
  echo "test_hostile: wrote $report"
  exit 0
fi

for step in "${steps[@]}"; do
  case "$step" in
    prepare | control | base | a | b | c | d | e | f | g | h | i) "step_$step" ;;
    *) echo "test_hostile: no step '$step'" >&2; exit 2 ;;
  esac
done
if [ "$failures" -ne 0 ]; then
  echo "test_hostile: $failures checks failed (runs in $work/runs, the autograder in $ag)"
  exit 1
fi
echo "test_hostile: all checks passed"
