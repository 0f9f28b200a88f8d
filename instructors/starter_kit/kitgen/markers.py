"""Solution regions: stripped to their STUB lines (or kept, for a part given
solved), and a hint where stripping empties a helper namespace.
"""
import re

from kitgen.base import KitError


BEGIN = re.compile(r"^(\s*)// BEGIN SOLUTION\s*$")
END = re.compile(r"^\s*// END SOLUTION\s*$")
STUB = re.compile(r"^\s*// STUB: ?(.*)$")


def strip_regions(path, lines, keep=False):
    """Returns (kit lines, solution lines, regions) for one file; regions
    are (BEGIN line, END line) pairs, 1-based and inclusive. With keep (a
    part given solved) the kit lines hold each region's solution instead of
    its stubs, and no line counts as solution."""
    out, solution, regions = [], [], []
    inside, indent, begin_line, stubs = False, "", 0, []
    # A region without stubs between two blank lines would leave two blank
    # lines in a row: the second goes.
    drop_blank = False
    for number, line in enumerate(lines, 1):
        if drop_blank:
            drop_blank = False
            if not line.strip():
                continue
        m = BEGIN.match(line)
        if m:
            if inside:
                raise KitError(f"{path}:{number}: BEGIN SOLUTION inside the region opened at line {begin_line}")
            inside, indent, begin_line, stubs = True, m.group(1), number, []
            continue
        if END.match(line):
            if not inside:
                raise KitError(f"{path}:{number}: END SOLUTION without BEGIN SOLUTION")
            if not keep:
                out.extend(indent + s + "\n" for s in stubs)
            regions.append((begin_line, number))
            inside = False
            drop_blank = not keep and not stubs and bool(out) and not out[-1].strip()
            continue
        if inside:
            s = STUB.match(line)
            if s:
                stubs.append(s.group(1))
            elif keep:
                out.append(line)
            else:
                solution.append(line)
            continue
        out.append(line)
    if inside:
        raise KitError(f"{path}:{begin_line}: BEGIN SOLUTION never closed")
    return out, solution, regions


EMPTY_NAMESPACE_OPEN = re.compile(r"^(\s*)namespace\s*\{\s*$")
NAMESPACE_CLOSE = re.compile(r"^\s*\}\s*//\s*namespace\s*$")
HELPERS_HINT = "// Your helper functions go here."


def mark_empty_helper_namespaces(lines):
    """An unnamed namespace left with nothing but blank lines (its helpers
    were solution code) gets one comment line saying what it is for."""
    out, i = [], 0
    while i < len(lines):
        m = EMPTY_NAMESPACE_OPEN.match(lines[i])
        if m:
            j = i + 1
            while j < len(lines) and not lines[j].strip():
                j += 1
            if j < len(lines) and NAMESPACE_CLOSE.match(lines[j]):
                out += [lines[i], "\n", m.group(1) + HELPERS_HINT + "\n", "\n", lines[j]]
                i = j + 1
                continue
        out.append(lines[i])
        i += 1
    return out
