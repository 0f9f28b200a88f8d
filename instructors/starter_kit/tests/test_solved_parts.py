#!/usr/bin/env python3
"""The starter-kit generator's --solved-parts (a kit that gives some parts
solved, such as parts 1-5 for the course's Project 3-2), on small made-up
trees and on a copy of this tree's stages/.

    test_solved_parts.py CHECK SOURCE_DIR

Each CHECK writes its trees into a temporary folder, copies the generator
into them, runs it, and exits 0 when the generator did what the check
names, 1 (with the reason) when not.
"""
import os
import re
import sys

sys.dont_write_bytecode = True  # the shared module beside this file leaves no compiled files in the tree
from kit_test_support import (FAST_PATH, base_tree, copy_stages, dedent, expect, expect_failure, expect_success,
                              generate, read, readme, run_checks)

OVERLAY = "instructors/starter_kit/overlay/"
PART1_SOLUTION = "const int doubled_and_offset_value = x * scale + 1;"
PART2_SOLUTION = "const int grown_by_the_solution_only = x * x + 7;"


def two_part_tree(extra=None):
    """base_tree's part 1 with a reference-only header, a part 2 beside it,
    a test with a region, and the students' documents."""
    files = base_tree({
        "stages/part1_demo/fast_path.h": FAST_PATH,
        "stages/part2_more/more.h": "#pragma once\nnamespace pt {\nint grow(int x);\n}  // namespace pt\n",
        "stages/part2_more/more.cpp": dedent(f"""
            #include "more.h"
            #include "todo.h"

            namespace pt {{

            int grow(int x) {{
              // BEGIN SOLUTION
              // STUB: PT_TODO(2);
              // STUB: return x;
              {PART2_SOLUTION}
              return grown_by_the_solution_only;
              // END SOLUTION
            }}

            }}  // namespace pt
            """),
        "stages/part2_more/README.md": readme("Part 2: more", (("more.h", "whole file"),)),
        "tests/part1/test_layout.cpp": dedent("""
            void check_all() {
              // BEGIN SOLUTION
              check_the_reference_layout_of_the_solution();
              // END SOLUTION
            }
            """),
        OVERLAY + "README.md": "# Starter kit\n\nYou write the parts.\n",
        OVERLAY + "stages_README.md": "# stages/\n\nOne folder per part.\n",
        OVERLAY + "grader_README.md": "# Grader\n",
        OVERLAY + "run.sh": "#!/bin/sh\n",
    })
    # The solution of part 1 includes its reference-only header.
    files["stages/part1_demo/work.cpp"] = files["stages/part1_demo/work.cpp"].replace(
        '#include "todo.h"\n', '#include "todo.h"\n// BEGIN SOLUTION\n#include "fast_path.h"\n// END SOLUTION\n')
    files.update(extra or {})
    return files


def check_solved_part_keeps_its_solution_stubbed_part_loses_it(tmp):
    """With --solved-parts 1, part 1's folder keeps its solution without
    markers, stubs or TODO lines, and its reference-only header; part 2 is
    stubbed as usual, and a test's region is stubbed in every kit; the
    kit's README, stages/README.md and part 1's README say that part 1 is
    given solved and part 2 is the students' (the README points to part 2's
    check), part 2's README says what part 1 gives; solved_parts.txt lists
    1."""
    run = generate(two_part_tree(), tmp)
    expect_success(run, "the kit without --solved-parts")
    expect(PART1_SOLUTION not in read(run, "stages/part1_demo/work.cpp"), "without the option part 1 is solved")
    expect("solved" not in read(run, "README.md"), "without the option the README speaks of solved parts")

    run = generate(two_part_tree({"scripts/check.sh": "#!/bin/sh\n"}), tmp, options=("--solved-parts", "1"))
    expect_success(run, "--solved-parts 1")
    expect("(part 1 given solved)" in run.out, f"the summary does not name the solved part: {run.out}")
    expect("first part's check is `scripts/check.sh 2`" in read(run, "README.md"),
           f"the kit's README does not point to the first stubbed part's check:\n{read(run, 'README.md')}")
    work = read(run, "stages/part1_demo/work.cpp")
    expect(PART1_SOLUTION in work and '#include "fast_path.h"' in work, f"part 1's solution is not in the kit:\n{work}")
    expect(not re.search(r"SOLUTION|STUB:|PT_TODO", work), f"part 1 keeps markers, stubs or a TODO line:\n{work}")
    expect(os.path.exists(os.path.join(run.dest, "stages/part1_demo/fast_path.h")),
           "part 1's reference-only header, which its solution includes, is not in the kit")
    more = read(run, "stages/part2_more/more.cpp")
    expect("  PT_TODO(2);\n  return x;\n" in more, f"part 2 is not stubbed:\n{more}")
    expect("grown_by_the_solution_only" not in more and "SOLUTION" not in more, f"part 2's solution is in the kit:\n{more}")
    test = read(run, "tests/part1/test_layout.cpp")
    expect("check_the_reference_layout" not in test, "a region outside stages/ kept its solution")

    notes = {"README.md": "This kit gives part 1 solved.", "stages/README.md": "In this kit part 1 is given solved",
             "stages/part1_demo/README.md": "Given solved in this kit."}
    for rel, note in notes.items():
        text = read(run, rel)
        expect(note in text and "part 2" in text, f"{rel} does not say that part 1 is given solved and part 2 "
                                                  f"is the students':\n{text}")
        expect(text.startswith("# ") and text.split("\n")[2].startswith("> **"), f"{rel}: the note is not below "
                                                                                  f"the title:\n{text}")
    stubbed = read(run, "stages/part2_more/README.md")
    expect("Given solved in this kit." not in stubbed, f"part 2's README says it is solved:\n{stubbed}")
    expect("**In this kit part 1 is given solved**" in stubbed and "You write this part's functions." in stubbed,
           f"part 2's README does not say that part 1 is given solved and part 2 is the students':\n{stubbed}")
    expect(read(run, "solved_parts.txt").split("\n")[-2:] == ["1", ""],
           f"solved_parts.txt does not list part 1 alone:\n{read(run, 'solved_parts.txt')}")


def check_this_tree_with_parts_1_to_5_solved(tmp):
    """This tree's stages with --solved-parts 1-5: every region of parts
    1-5 keeps its solution (no marker or TODO line left there), part 2's
    reference-only files come along, and the files of parts 6-9 are the
    usual kit's, stubbed."""
    stages = copy_stages(tmp)
    run = generate(stages, tmp)
    expect_success(run, "this tree's stages")
    usual = {rel: read(run, rel) for rel in stages if rel.endswith((".h", ".cpp")) and
             os.path.exists(os.path.join(run.dest, rel))}
    run = generate(stages, tmp, options=("--solved-parts", "1-5"))
    expect_success(run, "this tree's stages with --solved-parts 1-5")
    for ref in ("bvh_wide.h", "bvh_binning.h"):
        expect(os.path.exists(os.path.join(run.dest, "stages/part2_bvh", ref)), f"part 2's {ref} is not in the kit")
    todo_parts = set()
    for rel, text in sorted(stages.items()):
        if not rel.endswith((".h", ".cpp")):
            continue
        kit = read(run, rel)
        if int(re.match(r"stages/part(\d+)_", rel).group(1)) <= 5:
            solution = [l.strip() for region in re.findall(r"// BEGIN SOLUTION\n(.*?)// END SOLUTION", text, re.S)
                        for l in region.split("\n") if l.strip() and not l.strip().startswith("// STUB:")]
            expect("PT_TODO" not in kit and "SOLUTION" not in kit, f"{rel}: a TODO line or marker in a solved part")
            missing = [l for l in solution if l not in kit]
            expect(not missing, f"{rel}: solution lines missing from a solved part: {missing[:3]}")
        else:
            expect(kit == usual[rel], f"{rel}: not the usual kit's file (parts 6-9 are stubbed as usual)")
            todo_parts.update(int(n) for n in re.findall(r"PT_TODO(?:_AS)?\((\d+)", kit))
    expect(todo_parts == {6, 7, 8, 9}, f"TODO lines of parts {sorted(todo_parts)} in the kit, expected 6-9")


def check_this_tree_3_2_kit_says_what_parts_1_to_5_give(tmp):
    """This tree's stages with --solved-parts 1-5: part 6's README says, under
    its title, that part 4's handling of mirror and glass is written (the
    course's Task 0, which part 6's README otherwise asks of whoever writes
    part 4); parts 7-9 say that parts 1-5 are given and nothing of part 4;
    solved_parts.txt lists 1 to 5, one a line. Without the option the READMEs
    get no note and solved_parts.txt lists no part."""
    stages = copy_stages(tmp)
    run = generate(stages, tmp, options=("--solved-parts", "1-5"))
    expect_success(run, "this tree's stages with --solved-parts 1-5")
    numbers = [l for l in read(run, "solved_parts.txt").split("\n") if l and not l.startswith("#")]
    expect(numbers == ["1", "2", "3", "4", "5"], f"solved_parts.txt lists {numbers}, expected 1 to 5")
    for part in (6, 7, 8, 9):
        rel = next(r for r in stages if re.match(rf"stages/part{part}_[^/]+/README.md$", r))
        text = read(run, rel)
        head = text.split("\n\n")[1]  # the paragraph under the title
        expect(head.startswith("> **In this kit parts 1-5 are given solved**"),
               f"{rel}: no note under the title saying parts 1-5 are given:\n{head}")
        says_part4 = "`at_least_one_bounce_radiance` already treats mirror and glass" in " ".join(
            l.lstrip("> ") for l in head.split("\n"))
        expect(says_part4 == (part == 6), f"{rel}: the note {'does not say' if part == 6 else 'says'} that part 4's "
                                          f"delta handling is given:\n{head}")
    part6 = read(run, "stages/part6_mirror_glass/README.md")
    expect("### Part 4's share (the course's Task 0)" in part6, "part 6's README has no section the note points to")

    run = generate(stages, tmp)
    expect_success(run, "this tree's stages")
    numbers = [l for l in read(run, "solved_parts.txt").split("\n") if l and not l.startswith("#")]
    expect(numbers == [], f"the kit without --solved-parts lists solved parts {numbers}")
    expect("given solved" not in read(run, "stages/part6_mirror_glass/README.md"),
           "without --solved-parts part 6's README speaks of parts given solved")


def check_leak_of_a_stubbed_part_caught_when_others_are_solved(tmp):
    """With --solved-parts 1, a line of part 2's solution (or of a stubbed
    part's reference-only file) quoted in the overlay or in the solved
    part's README still stops the generator; a line of part 1's solution,
    which the kit holds anyway, does not."""
    quoting = {
        "the overlay's README": (OVERLAY + "README.md", "# Starter kit\n\n    " + PART2_SOLUTION + "\n",
                                 "error: README.md:"),
        "a solved part's README": ("stages/part1_demo/README.md",
                                   readme("Part 1: demo", (("work.h", "whole file"),)) + "\n    " + PART2_SOLUTION + "\n",
                                   "stages/part1_demo/README.md:"),
    }
    for what, (rel, text, where) in quoting.items():
        run = generate(two_part_tree({rel: text}), tmp, options=("--solved-parts", "1"))
        expect_failure(run, where, "solution line leaked", PART2_SOLUTION, what=what)

    # Part 2's reference-only header is still left out, and still solution.
    fast2 = FAST_PATH.replace("fast_solve_with_vector_units", "fast_grow_with_vector_units")
    quote = "# Starter kit\n\n    " + fast2.split("\n")[3] + "\n"
    run = generate(two_part_tree({"stages/part2_more/fast_grow.h": fast2, OVERLAY + "README.md": quote}), tmp,
                   options=("--solved-parts", "1"))
    expect_failure(run, "error: README.md:", "solution line leaked", "fast_grow_with_vector_units",
                   what="the overlay quoting a stubbed part's reference-only file")

    run = generate(two_part_tree({OVERLAY + "README.md": "# Starter kit\n\n    " + PART1_SOLUTION + "\n"}), tmp,
                   options=("--solved-parts", "1"))
    expect_success(run, "the overlay quoting a line of the solved part")
    run = generate(two_part_tree({OVERLAY + "README.md": "# Starter kit\n\n    " + PART1_SOLUTION + "\n"}), tmp)
    expect_failure(run, "README.md:3:", "solution line leaked", what="the same quote without --solved-parts")


def check_this_tree_catches_a_leak_of_part_6_with_parts_1_to_5_solved(tmp):
    """This tree's stages with --solved-parts 1-5: a line of part 6's
    solution copied into part 1's README stops the generator."""
    stages = copy_stages(tmp)
    rel = "stages/part6_mirror_glass/specular.cpp"
    regions = re.compile(r"// BEGIN SOLUTION\n(.*?)// END SOLUTION", re.S)
    solution = {l.strip() for region in regions.findall(stages[rel]) for l in region.split("\n")
                if not l.strip().startswith("//")}
    # The longest line of part 6's solution that occurs nowhere else: a line
    # the kit may not hold.
    elsewhere = "\n".join(regions.sub("", t) if r == rel else t for r, t in stages.items())
    line = max((l for l in solution if l not in elsewhere), key=len)
    rel = "stages/part1_raytracing/README.md"
    run = generate(dict(stages, **{rel: stages[rel] + "\n    " + line + "\n"}), tmp, options=("--solved-parts", "1-5"))
    expect_failure(run, rel + ":", "solution line leaked", line, what="part 6's solution in part 1's README")


def check_bad_solved_parts_value_is_one_line_and_exit_2(tmp):
    """A --solved-parts value that is not a list of parts, names a part
    without a stage folder, or solves every part is one line on stderr
    naming --solved-parts, exit status 2, and no kit."""
    cases = [
        (("--solved-parts", "one"), "expected part numbers"),
        (("--solved-parts", "2-1"), "2-1"),
        (("--solved-parts", "0"), "'0'"),
        (("--solved-parts", "1,"), "'1,'"),
        (("--solved-parts", "3"), "part 3"),
        (("--solved-parts", "1-2"), "every part"),
        (("--solved-parts=1-2",), "every part"),
        (("--solved-parts=",), "''"),
    ]
    for options, needle in cases:
        run = generate(two_part_tree(), tmp, options=options)
        expect_failure(run, "--solved-parts", needle, what=" ".join(options), code=2)
    run = generate(two_part_tree(), tmp, options=("--solved-parts=2",))
    expect_success(run, "--solved-parts=2")


if __name__ == "__main__":
    sys.exit(run_checks(__doc__, globals()))
