#!/usr/bin/env bash
# Builds the Gradescope autograder zip.
#
#   instructors/gradescope/make_autograder.sh [OUT.zip]     (default: build/gradescope/autograder.zip)
#   instructors/gradescope/make_autograder.sh --unpacked DIR
#
# The zip holds, at its root:
#   setup.sh         Gradescope runs it once, as root, to install the Debian/Ubuntu
#                    packages and build the grader (and a stub pathtracer, to warm the build)
#   run_autograder   Gradescope runs it for every submission
#   project/         the student starter kit (instructors/starter_kit/make_starter_kit.py: no solution code),
#                    with grader/ (sources, cases.txt), scenes/ and reference_images/
#   sandbox.sh, submission_tools.py  what run_autograder uses: the build sandbox,
#                    the intake of a submission's sources, the feedback's filter
#   hidden/          the hidden cases (instructors/hidden_cases/, or HIDDEN_CASES=DIR):
#                    cases.txt, their camera files, references/; never in project/
#   README.md        this folder's README (settings to choose on Gradescope)
#   VERSION          the commit it was made from
#
# --unpacked DIR writes the same files to DIR instead of zipping them
# (instructors/batch/grade_folder.sh uses it).
#
# Every case of grader/cases.txt needs its reference in reference_images/;
# a missing one is an error, unless ALLOW_MISSING_REFERENCES=1 (for tests
# that point the grader at other references with GRADER_REFERENCES).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }

unpacked=""
out=""
case "${1:-}" in
  -h | --help) usage; exit 0 ;;
  --unpacked)
    [ $# -eq 2 ] || { usage >&2; exit 2; }
    unpacked=$2 ;;
  "") out=$root/build/gradescope/autograder.zip ;;
  *)
    [ $# -eq 1 ] || { usage >&2; exit 2; }
    out=$1 ;;
esac

command -v python3 >/dev/null || { echo "make_autograder: python3 is needed" >&2; exit 1; }

# References: one folder with meta.json per case.
missing=()
while read -r name _; do
  [ -f "$root/reference_images/$name/meta.json" ] || missing+=("$name")
done < <(grep -Ev '^[[:space:]]*(#|$)' "$root/grader/cases.txt")
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${ALLOW_MISSING_REFERENCES:-0}" = 1 ]; then
    echo "make_autograder: warning: no reference for ${#missing[@]} cases (ALLOW_MISSING_REFERENCES=1): ${missing[*]}" >&2
  else
    echo "make_autograder: error: no reference in reference_images/ for: ${missing[*]}" >&2
    echo "make_autograder: make them with: build/bin/grader make-references" >&2
    exit 1
  fi
fi

stage=$(mktemp -d "${TMPDIR:-/tmp}/autograder.XXXXXX")
trap 'rm -rf "$stage"' EXIT

# The tree students get; the grader and the case list are part of it.
python3 "$root/instructors/starter_kit/make_starter_kit.py" "$stage/project" >/dev/null
# References and scenes as they are in this working tree (committed or not).
rm -rf "$stage/project/reference_images" "$stage/project/scenes"
cp -R "$root/reference_images" "$stage/project/reference_images"
cp -R "$root/scenes" "$stage/project/scenes"
grep -q 'add_subdirectory(grader)' "$stage/project/CMakeLists.txt" || {
  echo "make_autograder: error: CMakeLists.txt does not build the grader (no add_subdirectory(grader))" >&2
  exit 1
}

cp "$here/setup.sh" "$here/run_autograder" "$here/sandbox.sh" "$here/submission_tools.py" "$here/README.md" "$stage/"
chmod 755 "$stage/setup.sh" "$stage/run_autograder" "$stage/submission_tools.py"

# Hidden cases: graded, never in the kit (project/), root-only on Gradescope.
hidden_src=${HIDDEN_CASES:-$root/instructors/hidden_cases}
hidden_count=0
if [ -f "$hidden_src/cases.txt" ]; then
  cp -R "$hidden_src" "$stage/hidden"
  hidden_count=$(grep -Ecv '^[[:space:]]*(#|$)' "$hidden_src/cases.txt" || true)
elif [ -n "${HIDDEN_CASES:-}" ]; then
  echo "make_autograder: error: HIDDEN_CASES=$HIDDEN_CASES has no cases.txt" >&2
  exit 1
fi
{
  echo "commit: $(git -C "$root" rev-parse HEAD 2>/dev/null || echo unknown)"
  if [ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ]; then
    echo "working tree: modified"
  fi
  echo "made: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "cases: $(grep -Ecv '^[[:space:]]*(#|$)' "$root/grader/cases.txt")"
  echo "cases without a reference: ${#missing[@]}"
  echo "hidden cases: $hidden_count"
  # setup.sh checks the references unless some are missing on purpose.
  [ ${#missing[@]} -eq 0 ] || echo "reference check: off"
} >"$stage/VERSION"

if [ -n "$unpacked" ]; then
  mkdir -p "$unpacked"
  [ -z "$(ls -A "$unpacked")" ] || { echo "make_autograder: error: $unpacked is not empty" >&2; exit 1; }
  cp -R "$stage"/. "$unpacked"/
  echo "make_autograder: wrote $unpacked"
  exit 0
fi

mkdir -p "$(dirname "$out")"
out=$(cd "$(dirname "$out")" && pwd)/$(basename "$out")
rm -f "$out"
# Python's zipfile keeps the permission bits, so setup.sh and run_autograder
# stay executable when unzipped.
python3 - "$stage" "$out" <<'EOF'
import os, sys, zipfile
stage, out = sys.argv[1], sys.argv[2]
with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
    for dirpath, dirnames, filenames in os.walk(stage):
        dirnames.sort()
        for f in sorted(filenames):
            path = os.path.join(dirpath, f)
            z.write(path, os.path.relpath(path, stage))
EOF
echo "make_autograder: wrote $out ($(du -h "$out" | cut -f1))"
