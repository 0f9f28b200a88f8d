#!/usr/bin/env python3
"""Writes the student starter kit from the reference tree.

    instructors/starter_kit/make_starter_kit.py [--solved-parts PARTS] DEST

Copies every file of the repository (the files git lists: tracked ones and
new ones it does not ignore; every file when the tree is not a git
checkout) to DEST, replacing each region

    // BEGIN SOLUTION
    // STUB: <code>          (any number of these, optional)
    ... reference solution ...
    // END SOLUTION

by its STUB lines, uncommented and indented like the marker (a region
without STUB lines between two blank lines leaves one blank line).

Left out of the kit:
  - the instructors' folder, instructors/ (this generator, its overlay and
    tests, Gradescope packaging, batch grading, mutants, benchmarks, the
    scene generator, fuzzers: instructors/README.md), and CI (.ci/);
  - reference-only sources: a C++ file whose first line starts with
    "// REFERENCE ONLY" (e.g. the reference's SSE pair slab test), unless
    its part is given solved (--solved-parts, below). No file of the kit
    may #include one it leaves out, and no CMake file of the kit may name
    one;
  - reference-only documents: a Markdown file whose first line starts with
    "<!-- REFERENCE ONLY" (docs/benchmarks.md, about the reference's fast
    BVH). No Markdown file of the kit may link to one.

Installed over the copied files: the overlay files of
instructors/starter_kit/overlay/ (OVERLAY in kitgen/tree.py: the students'
README.md, stages/README.md, grader/README.md and scripts/run.sh).

Written by the generator: solved_parts.txt at the kit's root, the parts
the kit gives solved (comment lines starting with #, then one part number a
line; no number in a kit where every part is the students').

--solved-parts PARTS gives those parts solved: PARTS is a list of part
numbers and ranges (1-5; 1,2,3; 1-3,5). Their stage folders
(stages/partK_*/) keep the solution of every region, without the markers
and stubs, and their reference-only sources (the solution includes them);
every other part is stubbed as usual and checked as usual. `--solved-parts
1-5` is the kit for the course's Project 3-2: parts 1-5 (Project 3-1)
work, parts 6-9 are the students'. The kit's README.md, stages/README.md
and each part's README get a note (after their title) saying which parts
are given solved; a stubbed part's note also names what the solved parts
give it beyond their own functions (GIVEN_FOR in kitgen/solved.py: part
4's handling of mirror and glass, for part 6). A part without a stage folder, or every part
solved, is an error (exit status 2). Solution regions outside stage
folders (tests/) are stubbed in every kit.

An unnamed namespace that stripping leaves empty (it held only solution
helpers) gets a comment saying that the student's helpers go there.

Checks, all made before anything is written (on any failure: one line on
stderr naming the file and line, exit status 1, DEST left untouched):
  - markers: an END without BEGIN, a BEGIN inside a region or a region left
    open is an error;
  - given code: every namespace-level definition with a body (function,
    struct/class/union/enum, variable or constant with an initializer, a
    lambda held in a variable, a type alias) of a stage source
    (stages/**/*.h, *.cpp) that lies outside solution regions is either a
    function that contains a solution region itself (the function a student
    writes; the lines around its region are scaffolding), or listed under
    "## Given code" in its part's README. That section holds a Markdown
    table with a `file` column (backticked file names, relative to the part's
    folder) and a `given` column: "whole file", or backticked names as the
    definitions are written (`BVHNode`, `BVH::BVH`, `kRayEpsilon`). A
    listed file or name that does not exist, a "whole file" holding a
    solution region, and a listed name that is solution code are errors
    too, so the list stays true;
  - leaks: no solution line (of a region or of a reference-only file)
    appears in the kit (an overlay file or a document quoting one, say);
    lines that also occur in C++ code outside solution regions or in stubs,
    and short lines such as "}", "return L;" or "return false;", are not
    evidence;
  - links: every relative link of the kit's Markdown files points to a file
    or folder of the kit;
  - TODO lines: a PT_TODO(N) or PT_TODO_AS(N, ...) in stages/partK_*/ has
    N = K (the grader reads the part from the line a stub prints).
Exit status: 0 written and checked, 1 error, 2 a bad --solved-parts value.

This file is the command line and the writing of DEST; the work is done by
the modules of kitgen/ beside it (kitgen/__init__.py lists them).
"""
import os
import shutil
import sys
import tempfile

# The generator's modules live in kitgen/ beside this file; they are run
# from here, not installed, and leave no compiled files in the tree.
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from kitgen.base import KitError
from kitgen.scanner import definitions  # not used here: part of this module's interface
from kitgen.solved import SolvedPartsError, describe, parse_parts
from kitgen.tree import make_kit


def parse_arguments(argv):
    """(DEST, solved parts) from the command line; SolvedPartsError for a bad
    --solved-parts, None for anything else that is not DEST and options."""
    solved, rest = frozenset(), []
    k = 0
    while k < len(argv):
        arg = argv[k]
        if arg == "--solved-parts" or arg.startswith("--solved-parts="):
            if "=" in arg:
                value = arg.split("=", 1)[1]
            elif k + 1 < len(argv):
                k += 1
                value = argv[k]
            else:
                raise SolvedPartsError("--solved-parts needs a value such as 1-5")
            solved = parse_parts(value)
        else:
            rest.append(arg)
        k += 1
    if len(rest) != 1 or rest[0].startswith("-"):
        return None
    return rest[0], solved


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    try:
        parsed = parse_arguments(sys.argv[1:])
    except SolvedPartsError as e:
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 2
    if parsed is None:
        print(__doc__.strip())
        return 1
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    dest, solved = os.path.abspath(parsed[0]), parsed[1]
    if dest == root or dest.startswith(root + os.sep) and not dest.startswith(os.path.join(root, "build")):
        print(f"make_starter_kit: error: {dest}: choose a folder outside the repository (or under build/)",
              file=sys.stderr)
        return 1
    if os.path.exists(dest) and os.listdir(dest):
        print(f"make_starter_kit: error: {dest}: folder exists and is not empty", file=sys.stderr)
        return 1

    try:
        kit, origin, left_out, regions = make_kit(root, solved)
    except SolvedPartsError as e:
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 2
    except (KitError, OSError, UnicodeDecodeError) as e:
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 1

    # Written to a temporary folder beside DEST and renamed into place.
    parent = os.path.dirname(dest) or "."
    tmp = None
    try:
        os.makedirs(parent, exist_ok=True)
        tmp = tempfile.mkdtemp(prefix=".kit-", dir=parent)
        for rel, out in kit.items():
            target = os.path.join(tmp, rel)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            if out is None:
                shutil.copy2(origin[rel], target)
            else:
                with open(target, "w", encoding="utf-8") as f:
                    f.writelines(out)
                if origin[rel] is not None:  # None: a file the generator writes (solved_parts.txt)
                    shutil.copymode(origin[rel], target)
        if os.path.exists(dest):
            os.rmdir(dest)
        os.rename(tmp, dest)
    except OSError as e:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
        print(f"make_starter_kit: error: {e}", file=sys.stderr)
        return 1
    print(f"make_starter_kit: wrote {len(kit)} files with {regions} solution regions stubbed to {dest}"
          + (f" ({describe(solved)} given solved)" if solved else "")
          + (f" (left out as reference-only: {', '.join(left_out)})" if left_out else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
