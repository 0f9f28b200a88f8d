"""The "## Given code" table of each part's README, and the check that every
definition outside solution regions is listed there (and the list true).
"""
import os
import re

from kitgen.base import KitError
from kitgen.scanner import definitions


GIVEN_HEADING = re.compile(r"^##\s+Given code\s*$")
WHOLE_FILE = "whole file"


def table_cells(line):
    line = line.strip()
    if line.startswith("|"):
        line = line[1:]
    if line.endswith("|") and not line.endswith("\\|"):
        line = line[:-1]
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)]


def read_given(readme, lines):
    """{file (relative to the part folder): (set of names or WHOLE_FILE, line)}
    from the README's "## Given code" table; None without that section."""
    start = next((k for k, l in enumerate(lines) if GIVEN_HEADING.match(l)), None)
    if start is None:
        return None
    given = {}
    columns = None
    for k in range(start + 1, len(lines)):
        line = lines[k]
        number = k + 1
        if re.match(r"^#{1,2}\s", line):
            break
        if not line.lstrip().startswith("|"):
            if columns is not None and given:
                break  # the table ended
            continue
        cells = table_cells(line)
        if columns is None:
            names = [c.strip("`").lower() for c in cells]
            if "file" not in names or "given" not in names:
                raise KitError(f"{readme}:{number}: the Given code table needs a 'file' and a 'given' column")
            columns = (names.index("file"), names.index("given"))
            continue
        if all(re.fullmatch(r":?-+:?", c) for c in cells if c):
            continue  # the separator row
        if len(cells) <= max(columns):
            raise KitError(f"{readme}:{number}: Given code row has too few cells")
        files = re.findall(r"`([^`]+)`", cells[columns[0]])
        if not files:
            raise KitError(f"{readme}:{number}: Given code row names no `file`")
        cell = cells[columns[1]]
        if cell.lower() == WHOLE_FILE:
            what = WHOLE_FILE
        elif re.fullmatch(r"`[^`]+`(\s*,\s*`[^`]+`)*", cell):
            what = {re.sub(r"\s+", "", x) for x in re.findall(r"`([^`]+)`", cell)}
        else:
            raise KitError(f"{readme}:{number}: the given column holds '{WHOLE_FILE}' or backticked names, "
                           f"not: {cell}")
        for f in files:
            previous = given.get(f, (set(), number))[0]
            if WHOLE_FILE in (previous, what):
                given[f] = (WHOLE_FILE, number)
            else:
                given[f] = (previous | what, number)
    if columns is None:
        raise KitError(f"{readme}:{start + 1}: the Given code section has no table")
    return given


def stage_readme(rel):
    """stages/<part>/x.cpp -> stages/<part>/README.md (stages/README.md for
    files directly in stages/)."""
    parts = rel.split("/")
    return "/".join(parts[:2] + ["README.md"]) if len(parts) > 2 else "stages/README.md"


def check_given_code(root, sources):
    """sources: {stage source path: (text, regions)}, reference-only files
    excluded. Raises KitError for code outside solution regions that its
    part's README does not list as given, and for a list that is not true."""
    by_readme = {}
    for rel in sorted(sources):
        by_readme.setdefault(stage_readme(rel), []).append(rel)
    problems = []
    for readme, files in sorted(by_readme.items()):
        path = os.path.join(root, readme)
        lines = open(path, encoding="utf-8").read().split("\n") if os.path.isfile(path) else []
        given = read_given(readme, lines) or {}
        folder = os.path.dirname(readme)
        found = {}
        for rel in files:
            text, regions = sources[rel]
            in_region = lambda line: any(b <= line <= e for b, e in regions)
            local = os.path.relpath(rel, folder)
            listed, _ = given.get(local, (set(), 0))
            outside = {}
            for d in definitions(rel, text):
                if in_region(d.first_line):
                    continue
                contains_region = any(d.first_line < b and e <= d.last_line for b, e in regions)
                outside.setdefault(d.name, []).append((d, contains_region))
                if d.kind == "function" and contains_region:
                    continue  # the student's function; its lines around the region are scaffolding
                if listed == WHOLE_FILE or d.name in listed:
                    continue
                problems.append(f"{rel}:{d.first_line}: {d.kind} {d.name} is outside the solution markers and not "
                                f"listed as given in {readme} (## Given code)")
            found[local] = (outside, regions)
        for local, (what, number) in sorted(given.items(), key=lambda x: x[1][1]):
            if local not in found:
                problems.append(f"{readme}:{number}: `{local}` is listed as given but is not a source file of "
                                f"{folder}/ that the kit ships")
                continue
            outside, regions = found[local]
            if what == WHOLE_FILE:
                if regions:
                    problems.append(f"{readme}:{number}: `{local}` is listed as a whole given file but holds a "
                                    f"solution region (line {regions[0][0]})")
                continue
            for name in sorted(what):
                if name not in outside:
                    problems.append(f"{readme}:{number}: `{name}` is listed as given but {local} defines no {name} "
                                    f"outside solution regions")
                elif all(d.kind == "function" and holds for d, holds in outside[name]):
                    problems.append(f"{readme}:{number}: `{name}` is listed as given but holds a solution region "
                                    f"(the student writes it)")
    if problems:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise KitError(problems[0] + more)
