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
