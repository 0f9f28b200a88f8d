"""The checks on the kit as a whole: no #include or CMake mention of a
left-out file, links that resolve, no solution line leaked, TODO lines
naming their folder's part.
"""
import os
import re

from kitgen.base import SOURCE_EXTENSIONS, KitError


# Shorter lines ("}", "return L;") and lines of fewer words ("return false;")
# prove nothing.
MIN_LEAK_LENGTH = 12
MIN_LEAK_WORDS = 3
TODO_CALL = re.compile(r"\bPT_TODO(?:_AS)?\s*\(\s*(\d+)")
PART_FOLDER = re.compile(r"^stages/part(\d+)_")


INCLUDE = re.compile(r'^\s*#\s*include\s*["<]([^">]+)[">]')


def check_left_out_references(kit, left_out):
    """No kit source #includes a left-out file; no kit CMake file names one."""
    if not left_out:
        return
    for rel, out in sorted(kit.items()):
        if out is None:
            continue
        for number, line in enumerate(out, 1):
            if rel.endswith(SOURCE_EXTENSIONS):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                local = os.path.normpath(os.path.join(os.path.dirname(rel), target))
                for gone in left_out:
                    if local == gone or gone.endswith("/" + target) or gone == target:
                        raise KitError(f"{rel}:{number}: #include \"{target}\" names {gone}, which the kit leaves "
                                       f"out (REFERENCE ONLY); keep the #include inside a solution region")
            elif rel.endswith(("CMakeLists.txt", ".cmake")):
                for gone in left_out:
                    if re.search(r"(?<![\w.])" + re.escape(os.path.basename(gone)) + r"(?![\w.])", line):
                        raise KitError(f"{rel}:{number}: names {gone}, which the kit leaves out (REFERENCE ONLY)")


MD_LINK = re.compile(r"\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def check_links(kit):
    """Every relative link of the kit's Markdown files points into the kit."""
    present = set(kit)
    folders = {os.path.dirname(p) for p in present}
    for f in list(folders):
        while f:
            f = os.path.dirname(f)
            folders.add(f)
    for rel, out in sorted(kit.items()):
        if out is None or not rel.endswith(".md"):
            continue
        fenced = False
        for number, line in enumerate(out, 1):
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if fenced:
                continue
            for target in MD_LINK.findall(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                    continue
                path = target.split("#")[0]
                if path.startswith("/"):
                    raise KitError(f"{rel}:{number}: link to an absolute path: {target}")
                resolved = os.path.normpath(os.path.join(os.path.dirname(rel), path))
                if resolved.startswith(".."):
                    raise KitError(f"{rel}:{number}: link outside the kit: {target}")
                if resolved not in present and (resolved if resolved != "." else "") not in folders:
                    raise KitError(f"{rel}:{number}: link to {target}, which the kit does not contain")


def check_todo_parts(rel, lines):
    """A stub's PT_TODO names the part of the folder it is in."""
    folder = PART_FOLDER.match(rel)
    if not folder:
        return
    for number, line in enumerate(lines, 1):
        for m in TODO_CALL.finditer(line):
            if m.group(1) != folder.group(1):
                raise KitError(f"{rel}:{number}: PT_TODO names part {m.group(1)} in a part {folder.group(1)} folder "
                               f"(the grader reads the part from the TODO line)")


def check_leaks(kit, solution_lines, outside_lines):
    evidence = {l for l in solution_lines - outside_lines
                if len(l) >= MIN_LEAK_LENGTH and len(re.findall(r"\w+", l)) >= MIN_LEAK_WORDS}
    for rel, out in sorted(kit.items()):
        if out is None:
            continue
        for number, line in enumerate(out, 1):
            if line.strip() in evidence:
                raise KitError(f"{rel}:{number}: solution line leaked into the kit: {line.strip()}")


# Where the kit's documents may name what the kit does not hold: what its
# commands write (builds, outputs, the viewer's npm packages).
GENERATED = ("build", "out", "grader_out", "writeup/out", "viewer/web/node_modules")
TARGET_IN_COMMAND = re.compile(r"--target((?:\s+[A-Za-z_][A-Za-z0-9_]*)+)")
DEFINED_TARGET = re.compile(r"\badd_(?:executable|library|custom_target)\(\s*([A-Za-z_][A-Za-z0-9_]*)")
KIT_TESTS = re.compile(r"\bpt_add_tests\(\s*([A-Za-z_][A-Za-z0-9_]*)\s+LABELS\s+\"?([^\"\n]*?)\"?\s+SOURCES")
LEFT_OUT_TEST = re.compile(r"\b(?:add_test\(\s*NAME|pt_kit_test\()\s*([A-Za-z_][A-Za-z0-9_]*)")


def check_doc_names(kit, left_out_cmake):
    """The kit's Markdown files name only what the kit has: every repository
    path they give (`stages/...`, `scripts/...`) is a file or folder of the
    kit (or what a command writes: GENERATED), every `--target` a target of
    the kit's CMake files, and no test of a left-out CMake file
    (left_out_cmake: their texts) by its name."""
    present = set(kit)
    folders = set()
    for f in present:
        while f:
            f = os.path.dirname(f)
            folders.add(f)
    tops = sorted({p.split("/")[0] for p in present if "/" in p} | {"instructors", ".ci"})
    path = re.compile(r"(?<![\w./-])((?:%s)/[A-Za-z0-9_./-]*[A-Za-z0-9_/])" % "|".join(map(re.escape, tops)))
    targets = set()
    for rel, out in kit.items():
        if out is not None and rel.endswith(("CMakeLists.txt", ".cmake")):
            text = "".join(out)
            targets.update(DEFINED_TARGET.findall(text))
            for name, labels in KIT_TESTS.findall(text):
                targets.add(name)
                targets.update(f"{label}_tests" for label in labels.split(";") if label)
    gone_tests = {t for text in left_out_cmake for t in LEFT_OUT_TEST.findall(text)}
    for rel, out in sorted(kit.items()):
        if out is None or not rel.endswith(".md"):
            continue
        for number, line in enumerate(out, 1):
            for p in path.findall(line):
                q = p.rstrip("/")
                if q in present or q in folders or any(q == g or q.startswith(g + "/") for g in GENERATED):
                    continue
                raise KitError(f"{rel}:{number}: names {p}, which the kit does not contain")
            for group in TARGET_IN_COMMAND.findall(line):
                for t in group.split():
                    if t not in targets:
                        raise KitError(f"{rel}:{number}: names the build target {t}, which the kit's CMake files "
                                       f"do not define")
            for word in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", line):
                if word in gone_tests:
                    raise KitError(f"{rel}:{number}: names the test {word}, which the kit does not have "
                                   f"(its CMake file is left out)")
