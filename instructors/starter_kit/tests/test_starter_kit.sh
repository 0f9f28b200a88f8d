#!/usr/bin/env bash
# The starter kit, end to end, in steps that share one generated kit and
# one build of it in WORK_DIR (ctest runs each step as a test of its own,
# instructors/starter_kit/CMakeLists.txt):
#   generate            write the kit (WORK_DIR/kit) from this tree
#   generate_3_2        write the kit for Project 3-2 (--solved-parts 1-5) instead
#   no_solution_code    no solution markers, no solution line, no
#                       instructors' or reference-only file in the kit
#   students_documents  the students' README, grader README and run.sh; no
#                       link to what the kit does not hold; no instructor-only name
#   build               configure the kit and build every target, with the
#                       stubs students get
#   renders             its pathtracer renders and names the missing function
#   run_sh              its scripts/run.sh renders, lists what is missing and
#                       grades (and with --part 1 grades part 1 alone)
#   readme_checks       each part README's check command (scripts/check.sh N)
#                       builds (on a fresh kit only what it needs) and runs the
#                       part's tests: a solved part's pass, a stubbed part's fail
#                       naming what to implement; nothing crashes; an unbuilt
#                       part's ctest fails saying it is not built
#   run_sh_3_2          the 3-2 kit's scripts/run.sh renders CBspheres.dae and
#                       lists the stubs of parts 6-9
#   reference_stages    with the reference's stages put back, every kit test
#                       a stage's code can change (labels part1-9, cli,
#                       scenes, course) passes (this changes the kit: it
#                       comes last)
#
#   test_starter_kit.sh [--step STEP] SOURCE_DIR WORK_DIR COURSE_SCENES
# Without --step, every step in this order but generate_3_2 and run_sh_3_2
# (the 3-2 kit's, in a WORK_DIR of its own: generate_3_2, readme_checks,
# run_sh_3_2). The timeouts it gives are
# multiplied by PT_TEST_TIMEOUT_SCALE (tests/timeout_scale/timeout_scale.sh).
set -euo pipefail
steps=(generate no_solution_code students_documents build renders run_sh readme_checks reference_stages)
if [ "${1:-}" = --step ]; then
  steps=("$2")
  shift 2
fi
[ $# -eq 3 ] || { echo "usage: test_starter_kit.sh [--step STEP] SOURCE_DIR WORK_DIR COURSE_SCENES" >&2; exit 2; }
src=$1 work=$2 course=$3
kit=$work/kit
jobs=$(nproc 2>/dev/null || echo 2)
# Through ccache where it is installed, as the kit's scripts/build.sh does:
# the kit's files that are this tree's are cache hits of its own build.
ccache=OFF
command -v ccache >/dev/null 2>&1 && ccache=ON
. "$src/tests/timeout_scale/timeout_scale.sh"

fail() { echo "FAIL: $*"; exit 1; }
need_kit() { [ -f "$kit/CMakeLists.txt" ] || fail "no kit in $kit: run the generate step first"; }
need_build() { [ -x "$kit/build/bin/pathtracer" ] || fail "no build of the kit in $kit/build: run the build step first"; }

step_generate() {
  rm -rf "$work"
  mkdir -p "$work"
  "$src/instructors/starter_kit/make_starter_kit.py" "$kit" || fail "the kit generator failed"
  echo "PASS: kit generated in $kit"
}

# The kit for Project 3-2: parts 1-5 given solved.
step_generate_3_2() {
  rm -rf "$work"
  mkdir -p "$work"
  "$src/instructors/starter_kit/make_starter_kit.py" --solved-parts 1-5 "$kit" || fail "the kit generator failed"
  grep -qx 5 "$kit/solved_parts.txt" || fail "the kit's solved_parts.txt does not list part 5"
  echo "PASS: the 3-2 kit generated in $kit"
}

# No solution code: no markers or stub comments left in any C++ file, no
# reference-only file, no instructor-only file, and no line of a solution
# (one that the reference has nowhere outside its solution regions).
step_no_solution_code() {
  need_kit
  grep -rlE --include="*.cpp" --include="*.h" --exclude-dir=build --exclude-dir=out "(BEGIN|END) SOLUTION|// STUB:" "$kit" \
    && fail "solution markers left in the kit"
  for gone in .ci instructors; do
    [ -e "$kit/$gone" ] && fail "the kit holds $gone/, which is for instructors only"
  done
  python3 - "$src" "$kit" <<'PY' || fail "solution code in the kit"
import os, re, sys
src, kit = sys.argv[1:]
def sources(root):
    for d, _, names in os.walk(root):
        if os.path.relpath(d, root).split(os.sep)[0].startswith(("build", ".git")):
            continue
        for n in names:
            if n.endswith((".h", ".cpp")):
                yield os.path.join(d, n)
solution, outside = set(), set()
for path in sources(src):
    lines = open(path, encoding="utf-8").read().split("\n")
    rel = os.path.relpath(path, src)
    if lines[0].startswith("// REFERENCE ONLY"):
        solution.update(l.strip() for l in lines)
        if os.path.exists(os.path.join(kit, rel)):
            sys.exit(f"{rel} is REFERENCE ONLY but in the kit")
        continue
    inside = False
    for l in lines:
        if "// BEGIN SOLUTION" in l or "// END SOLUTION" in l:
            inside = "BEGIN" in l
        elif inside and not l.strip().startswith("// STUB:"):
            solution.add(l.strip())
        else:
            outside.add(re.sub(r"^// STUB: ?", "", l.strip()))
evidence = {l for l in solution - outside if len(l) >= 12 and len(re.findall(r"\w+", l)) >= 3}
if len(evidence) < 100:
    sys.exit(f"only {len(evidence)} solution lines found in {src}: is this the reference tree?")
for d, dirs, names in os.walk(kit):
    dirs[:] = [x for x in dirs if not (d == kit and x in ("build", "out"))]
    for n in names:
        if n.endswith((".h", ".cpp", ".md", ".sh", ".py", ".txt")):
            path = os.path.join(d, n)
            for number, l in enumerate(open(path, encoding="utf-8"), 1):
                if l.strip() in evidence:
                    sys.exit(f"{os.path.relpath(path, kit)}:{number}: solution line: {l.strip()}")
PY
  echo "PASS: no solution code, no instructors' or reference-only file in the kit"
}

# The students' documents: their own README and grader README and run.sh,
# and no Markdown link to something the kit does not hold.
step_students_documents() {
  need_kit
  cmp -s "$kit/README.md" "$src/instructors/starter_kit/overlay/README.md" \
    || fail "the kit's README.md is not the students' (instructors/starter_kit/overlay/README.md)"
  cmp -s "$kit/grader/README.md" "$src/instructors/starter_kit/overlay/grader_README.md" \
    || fail "the kit's grader/README.md is not the students'"
  grep -q "Rendered with your build" "$kit/scripts/run.sh" || fail "the kit's scripts/run.sh does not say 'your build'"
  grep -q "Grading the reference build" "$kit/scripts/run.sh" && fail "the kit's scripts/run.sh speaks of the reference build"
  python3 - "$kit" <<'PY' || fail "broken links in the kit's Markdown files"
import os, re, sys
kit = sys.argv[1]
bad = []
for d, dirs, names in os.walk(kit):
    dirs[:] = [x for x in dirs if not (d == kit and x in ("build", "out"))]
    for n in names:
        if not n.endswith(".md"):
            continue
        path = os.path.join(d, n)
        text = re.sub(r"```.*?```", "", open(path, encoding="utf-8").read(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", re.sub(r"`[^`\n]*`", "", text)):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue
            if not os.path.exists(os.path.join(d, target.split("#")[0])):
                bad.append(f"{os.path.relpath(path, kit)}: {target}")
if bad:
    sys.exit("links to what the kit does not hold:\n  " + "\n  ".join(bad))
PY
  grep -rnE "instructors/|gradescope/|grade_mutants|mutants\.txt|mutants/|make_starter_kit|starter_kit/|fuzz_|fake_student|compare_embree|bvh_table\.sh|ray_bench" \
    --include="*.md" --exclude-dir=build --exclude-dir=out "$kit" && fail "the kit's documents mention instructor-only files"
  echo "PASS: the students' README, grader README and run.sh; every link resolves; no instructor-only name"
}

# Every target, as students build it with scripts/test.sh: the stubs must
# compile and link into everything.
step_build() {
  need_kit
  rm -rf "$kit/build"
  cmake -S "$kit" -B "$kit/build" -DCMAKE_BUILD_TYPE=Release -DPT_COURSE_SCENES="$course" -DPT_CCACHE="$ccache" >/dev/null \
    || fail "the kit does not configure"
  cmake --build "$kit/build" -j "$jobs" >"$work/build.log" 2>&1 || { tail -30 "$work/build.log"; fail "the kit does not build"; }
  echo "PASS: the kit as handed out builds every target"
}

# It runs and writes an image, saying which functions are missing.
step_renders() {
  need_build
  rm -f "$work/kit.png"
  "$kit/build/bin/pathtracer" --part 1 -r 32 24 -f "$work/kit.png" "$src/scenes/CBspheres_lambertian.dae" \
    >"$work/run.out" 2>"$work/run.err" || fail "the kit's pathtracer --part 1 failed: $(cat "$work/run.err")"
  [ -s "$work/kit.png" ] || fail "the kit's pathtracer wrote no image"
  grep -q "TODO: implement Part 1: generate_ray" "$work/run.err" || fail "no 'implement generate_ray' message"
  echo "PASS: the kit's pathtracer renders and names generate_ray"
}

# Its main script, on the unfinished kit: renders with the student's build,
# lists what is not implemented, grades the build on every case (each stops
# at its first TODO line) and says where the report is (exit status 1: cases
# fail); with arguments it grades only the cases they select. Skipped (exit
# 77) where packages are missing, as the script would stop to ask for them.
step_run_sh() {
  need_build
  if ! "$kit/scripts/setup.sh" --build-only >"$work/setup.log" 2>&1; then
    cat "$work/setup.log"
    echo "SKIPPED: packages are missing (scripts/setup.sh --build-only), so the kit's scripts/run.sh cannot run"
    exit 77
  fi
  rm -rf "$kit/out"
  local status=0
  (cd "$kit" && scripts/run.sh --part 1) >"$work/run_sh_part1.log" 2>&1 || status=$?
  [ "$status" -eq 1 ] || { tail -20 "$work/run_sh_part1.log"; fail "scripts/run.sh --part 1 exited $status, expected 1"; }
  grep -qE "^ +1 +p1_" "$work/run_sh_part1.log" && ! grep -qE "^ +[2-5] +p[2-5]_" "$work/run_sh_part1.log" \
    || fail "scripts/run.sh --part 1 did not grade part 1's cases alone"
  status=0
  (cd "$kit" && scripts/run.sh) >"$work/run_sh.log" 2>&1 || status=$?
  [ "$status" -eq 1 ] || { tail -20 "$work/run_sh.log"; fail "the kit's scripts/run.sh exited $status, expected 1"; }
  for want in "Rendered with your build: out/CBspheres_lambertian.png" \
              "Not implemented yet: Part 1: generate_ray (stages/part1_raytracing/camera_rays.cpp)" \
              "Your report: out/grade/report.html"; do
    grep -qF "$want" "$work/run_sh.log" || { tail -20 "$work/run_sh.log"; fail "the kit's scripts/run.sh did not print: $want"; }
  done
  grep -q "^TODO: implement" "$work/run_sh.log" && fail "the kit's scripts/run.sh printed raw TODO lines"
  grep -q "Part 1 not implemented" "$work/run_sh.log" \
    || fail "the kit's grading does not say that part 1 is not implemented"
  [ -s "$kit/out/CBspheres_lambertian.png" ] && [ -s "$kit/out/grade/report.html" ] \
    || fail "the kit's scripts/run.sh wrote no image or no report"
  echo "PASS: the kit's scripts/run.sh renders, lists what is missing, grades (part 1 alone with --part 1)"
}

# Each part README's check command, as the README writes it, run from the
# kit's root: it builds what the part's tests need (on a fresh kit, only
# that: no viewer, no grader), runs tests (never "No tests were found"),
# passes for a part the kit gives solved, and for a stubbed part fails,
# naming a function to write, with no crash or hang. A stubbed part's tests
# are stopped at their first failure (--stop-on-failure after the README's
# command: scripts/check.sh passes it to ctest), which is enough to see the
# message and keeps this check short (stubbed parts brute-force everything
# and run slowly). Skipped (77) where packages are missing, as check.sh
# would stop to ask for them.
step_readme_checks() {
  need_kit
  if ! "$kit/scripts/setup.sh" --build-only >"$work/setup.log" 2>&1; then
    cat "$work/setup.log"
    echo "SKIPPED: packages are missing (scripts/setup.sh --build-only), so the kit's scripts/check.sh cannot run"
    exit 77
  fi
  local fresh=0 part cmd log limit status ran
  [ -e "$kit/build/bin/pathtracer" ] || fresh=1
  limit=$(scaled_seconds 300)
  # The check command of every part's README (its "How to check your work").
  python3 - "$kit" >"$work/readme_checks.txt" <<'PY' || fail "a part README gives no check command"
import glob, os, re, sys
kit = sys.argv[1]
for readme in sorted(glob.glob(os.path.join(kit, "stages", "part*_*", "README.md"))):
    part = re.search(r"part(\d+)_", readme).group(1)
    text = open(readme, encoding="utf-8").read()
    section = text.split("## How to check your work", 1)[-1].split("\n## ", 1)[0]
    m = re.search(r"`(scripts/check\.sh[^`]*)`", section)
    if not m:
        sys.exit(f"{os.path.relpath(readme, kit)}: no scripts/check.sh command under 'How to check your work'")
    print(part, m.group(1))
PY
  [ "$(wc -l <"$work/readme_checks.txt")" -eq 9 ] || fail "expected the check commands of 9 part READMEs: $(cat "$work/readme_checks.txt")"
  if [ "$fresh" = 1 ]; then
    # Before anything is built, ctest alone must not pass a part: the
    # placeholder of an unbuilt test executable fails, saying so.
    cmake -S "$kit" -B "$kit/build" -DCMAKE_BUILD_TYPE=Release -DPT_COURSE_SCENES="$course" -DPT_CCACHE="$ccache" >/dev/null \
      || fail "the kit does not configure"
    ctest --test-dir "$kit/build" -L part6 >"$work/unbuilt.log" 2>&1 \
      && { cat "$work/unbuilt.log"; fail "ctest -L part6 passed on a kit whose tests were never built"; }
    grep -q "test_part6: NOT BUILT (run scripts/check.sh 6)" "$work/unbuilt.log" \
      || { cat "$work/unbuilt.log"; fail "ctest -L part6 on an unbuilt kit does not say that the tests are not built"; }
  fi
  while read -r part cmd; do
    log=$work/check$part.log
    status=0
    if grep -qx "$part" "$kit/solved_parts.txt"; then
      (cd "$kit" && $cmd) >"$log" 2>&1 || status=$?
      [ "$status" -eq 0 ] || { tail -30 "$log"; fail "part $part is given solved, but its README's '$cmd' exited $status"; }
    else
      (cd "$kit" && $cmd --stop-on-failure --timeout "$limit") >"$log" 2>&1 || status=$?
      [ "$status" -ne 0 ] || { tail -30 "$log"; fail "part $part's README's '$cmd' passed with the stubs"; }
      grep -q "TODO: implement Part" "$log" || { tail -30 "$log"; fail "part $part's failures do not say what to implement"; }
      grep -qE "SEGFAULT|Child aborted|Subprocess aborted|Exception: |Timeout" "$log" \
        && { tail -30 "$log"; fail "part $part's tests crashed or hung with the stubs"; }
    fi
    grep -q "No tests were found" "$log" && fail "part $part's README's '$cmd' found no tests"
    ran=$(sed -n 's/.* tests failed out of \([0-9]*\)$/\1/p' "$log" | tail -1)
    [ "${ran:-0}" -ge 1 ] || { tail -30 "$log"; fail "part $part's README's '$cmd' ran no test"; }
    echo "part $part: '$cmd' ran tests (ctest: $(grep -E 'tests passed' "$log" | tail -1)), exit status $status"
  done <"$work/readme_checks.txt"
  if [ "$fresh" = 1 ]; then
    for t in viewer grader test_common test_debugger; do
      [ -e "$kit/build/bin/$t" ] && fail "the part checks built $t, which no part's tests need"
    done
  fi
  echo "PASS: every part README's check command builds and runs its part's tests"
}

# The kit for Project 3-2 (parts 1-5 given solved) starts on 3-2: its
# scripts/run.sh renders the course's mirror and glass scene and lists the
# functions of parts 6 to 9 still to write (with --part 6 it grades part
# 6's cases alone). Skipped (77) where packages are missing.
step_run_sh_3_2() {
  need_kit
  grep -qx 5 "$kit/solved_parts.txt" || fail "this kit does not give part 5 solved: not the kit for Project 3-2"
  if ! "$kit/scripts/setup.sh" --build-only >"$work/setup.log" 2>&1; then
    cat "$work/setup.log"
    echo "SKIPPED: packages are missing (scripts/setup.sh --build-only), so the kit's scripts/run.sh cannot run"
    exit 77
  fi
  rm -rf "$kit/out"
  local status=0 part
  (cd "$kit" && scripts/run.sh --part 6) >"$work/run_sh.log" 2>&1 || status=$?
  [ "$status" -eq 1 ] || { tail -20 "$work/run_sh.log"; fail "the 3-2 kit's scripts/run.sh --part 6 exited $status, expected 1"; }
  grep -qF "Rendered with your build: out/CBspheres.png" "$work/run_sh.log" \
    || { tail -20 "$work/run_sh.log"; fail "the 3-2 kit's scripts/run.sh did not render scenes/CBspheres.dae"; }
  for part in 6 7 8 9; do
    grep -q "^Not implemented yet: Part $part: " "$work/run_sh.log" \
      || { cat "$work/run_sh.log"; fail "the 3-2 kit's scripts/run.sh does not list part $part's stubs"; }
  done
  grep -q "^Not implemented yet: Part [1-5]: " "$work/run_sh.log" && fail "the 3-2 kit lists a stub of a solved part"
  grep -qE "^ +6 +p6_.*Part 6 not implemented" "$work/run_sh.log" && ! grep -qE "^ +[1-57-9] +p[1-57-9]_" "$work/run_sh.log" \
    || { tail -20 "$work/run_sh.log"; fail "scripts/run.sh --part 6 did not grade part 6's cases alone, as not implemented"; }
  [ -s "$kit/out/CBspheres.png" ] && [ ! -e "$kit/out/todo_probe.png" ] \
    || fail "the 3-2 kit's scripts/run.sh wrote no out/CBspheres.png, or left its probe's image"
  echo "PASS: the 3-2 kit's scripts/run.sh renders CBspheres.dae and lists the stubs of parts 6 to 9"
}

# With the reference's stages the kit is the reference: its tests pass.
step_reference_stages() {
  need_build
  # Only the files that differ are replaced (and the reference-only ones
  # added): a file copied unchanged would get a new time and make would
  # recompile everything that includes it.
  local f
  (cd "$src/stages" && find . -type f) | while IFS= read -r f; do
    cmp -s "$src/stages/$f" "$kit/stages/$f" || { mkdir -p "$(dirname "$kit/stages/$f")" && cp "$src/stages/$f" "$kit/stages/$f"; }
  done
  (cd "$kit/stages" && find . -type f) | while IFS= read -r f; do
    [ -e "$src/stages/$f" ] || rm "$kit/stages/$f"
  done
  diff -r "$src/stages" "$kit/stages" >/dev/null || fail "the kit's stages/ could not be made the reference's"
  cmake --build "$kit/build" -j "$jobs" >"$work/build2.log" 2>&1 \
    || { tail -30 "$work/build2.log"; fail "rebuild with the reference stages failed"; }
  # The tests a stage's code can change: every part's, and those that run
  # the pathtracer on the command line and on the scenes. The rest (the
  # grader's, the viewer's, the write-up's) are this tree's own tests on the
  # same files, which the suite runs already.
  local labels='^(part[1-9]|cli|scenes|course)$' count
  count=$(ctest --test-dir "$kit/build" -N -L "$labels" | sed -n 's/^Total Tests: *//p')
  [ "${count:-0}" -ge 100 ] || fail "the kit has only ${count:-0} tests of the parts, the command line and the scenes"
  ctest --test-dir "$kit/build" -j "$jobs" -L "$labels" >"$work/reference.log" 2>&1 \
    || { grep -E "Failed|\*\*\*" "$work/reference.log" | head -20; fail "the kit with the reference's stages fails tests"; }
  echo "PASS: with the reference's stages the kit's $count tests of the parts, the command line and the scenes pass"
}

for step in "${steps[@]}"; do
  case "$step" in
    generate | generate_3_2 | no_solution_code | students_documents | build | renders | run_sh | readme_checks \
      | run_sh_3_2 | reference_stages)
      "step_$step" ;;
    *) echo "test_starter_kit.sh: no step '$step'" >&2; exit 2 ;;
  esac
done
