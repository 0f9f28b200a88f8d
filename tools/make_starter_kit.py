#!/usr/bin/env python3
"""Writes the student starter kit from the reference tree.

    tools/make_starter_kit.py DEST

Copies every file of the repository (as git lists it; without .git, .ci
and the instructors' grading tools: the Gradescope packaging, batch
grading and the mutant table, which only make sense in the reference tree)
to DEST, replacing each region

    // BEGIN SOLUTION
    // STUB: <code>          (any number of these, optional)
    ... reference solution ...
    // END SOLUTION

by its STUB lines, uncommented and indented like the marker. Markers are
validated first: an END without BEGIN, a BEGIN inside a region or a region
left open is an error naming the file and line, and nothing is written.
Afterwards every file of the kit is checked: no solution line may appear in
it (lines of the solution that also occur outside solution regions of the
reference, and short lines such as "}" or "return L;", are not evidence).
Exit status: 0 written and checked, 1 error.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

BEGIN = re.compile(r"^(\s*)// BEGIN SOLUTION\s*$")
END = re.compile(r"^\s*// END SOLUTION\s*$")
STUB = re.compile(r"^\s*// STUB: ?(.*)$")
# Left out of the kit: CI, and tools that act on the reference tree.
INSTRUCTOR_ONLY = (".ci/", "grader/gradescope/", "grader/batch/", "grader/grade_mutants.sh", "grader/mutants/",
                   "grader/mutants.txt", "grader/tables/mutants.md")
MIN_LEAK_LENGTH = 12  # shorter lines ("}", "return L;") prove nothing


class MarkerError(Exception):
    pass


def strip_regions(path, lines):
    """Returns (kit lines, solution lines) for one file."""
    out, solution = [], []
    inside, indent, begin_line, stubs = False, "", 0, []
    for number, line in enumerate(lines, 1):
        m = BEGIN.match(line)
        if m:
            if inside:
                raise MarkerError(f"{path}:{number}: BEGIN SOLUTION inside the region opened at line {begin_line}")
            inside, indent, begin_line, stubs = True, m.group(1), number, []
            continue
        if END.match(line):
            if not inside:
                raise MarkerError(f"{path}:{number}: END SOLUTION without BEGIN SOLUTION")
            out.extend(indent + s + "\n" for s in stubs)
            inside = False
            continue
        if inside:
            s = STUB.match(line)
            if s:
                stubs.append(s.group(1))
            else:
                solution.append(line)
            continue
        out.append(line)
    if inside:
        raise MarkerError(f"{path}:{begin_line}: BEGIN SOLUTION never closed")
    return out, solution


def tracked_files(root):
    try:
        listed = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
        files = [f for f in listed.decode().split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = [d for d in dirnames if d not in (".git", "build") and not d.startswith("build")]
            files += [os.path.relpath(os.path.join(dirpath, f), root) for f in filenames]
    return sorted(f for f in files
                  if not f.startswith(INSTRUCTOR_ONLY) and os.path.isfile(os.path.join(root, f)))


def is_text(path):
    return path.endswith((".h", ".hpp", ".cpp", ".cc", ".txt", ".cmake", ".md", ".sh", ".py"))


def is_source(path):
    # Only C++ sources carry solution regions; documents show the markers
    # as examples and are copied unchanged.
    return path.endswith((".h", ".hpp", ".cpp", ".cc"))


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(sys.argv) == 2 else 1
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    dest = os.path.abspath(sys.argv[1])
    if dest == root or dest.startswith(root + os.sep) and not dest.startswith(os.path.join(root, "build")):
        print(f"make_starter_kit: error: {dest}: choose a folder outside the repository (or under build/)",
              file=sys.stderr)
        return 1
    if os.path.exists(dest) and os.listdir(dest):
        print(f"make_starter_kit: error: {dest}: folder exists and is not empty", file=sys.stderr)
        return 1

    files = tracked_files(root)
    kit, solution_lines, outside_lines, regions = {}, set(), set(), 0
    try:
        for rel in files:
            src = os.path.join(root, rel)
            if not is_text(rel):
                kit[rel] = None  # copied as is
                continue
            with open(src, encoding="utf-8") as f:
                lines = f.readlines()
            out, solution = strip_regions(rel, lines) if is_source(rel) else (lines, [])
            if solution or len(out) != len(lines):
                regions += sum(1 for l in lines if BEGIN.match(l))
            kit[rel] = out
            solution_lines.update(l.strip() for l in solution)
            outside_lines.update(l.strip() for l in out)
    except MarkerError as e:
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 1

    # Build in a temporary folder beside DEST and rename it into place.
    parent = os.path.dirname(dest) or "."
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=".kit-", dir=parent)
    try:
        for rel, out in kit.items():
            target = os.path.join(tmp, rel)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            if out is None:
                shutil.copy2(os.path.join(root, rel), target)
            else:
                with open(target, "w", encoding="utf-8") as f:
                    f.writelines(out)
                shutil.copymode(os.path.join(root, rel), target)
        # The leak check, over the written files.
        evidence = {l for l in solution_lines - outside_lines if len(l) >= MIN_LEAK_LENGTH}
        for rel, out in kit.items():
            if out is None:
                continue
            for number, line in enumerate(out, 1):
                if line.strip() in evidence:
                    raise MarkerError(f"{rel}:{number}: solution line leaked into the kit: {line.strip()}")
        if os.path.exists(dest):
            os.rmdir(dest)
        os.rename(tmp, dest)
    except (MarkerError, OSError) as e:
        shutil.rmtree(tmp, ignore_errors=True)
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 1
    print(f"make_starter_kit: wrote {len(kit)} files with {regions} solution regions stubbed to {dest}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
