#!/usr/bin/env python3
"""Writes the student starter kit from the reference tree.

    instructors/starter_kit/make_starter_kit.py DEST

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
    "// REFERENCE ONLY" (e.g. the reference's SSE pair slab test). No file of
    the kit may #include one, and no CMake file of the kit may name one;
  - reference-only documents: a Markdown file whose first line starts with
    "<!-- REFERENCE ONLY" (docs/benchmarks.md, about the reference's fast
    BVH). No Markdown file of the kit may link to one.

Installed over the copied files: the overlay files of
instructors/starter_kit/overlay/ (OVERLAY below: the students' README.md,
stages/README.md, grader/README.md and scripts/run.sh).

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
    appears in the kit (an overlay file quoting one, say); lines that also
    occur outside solution regions of the reference or in stubs, and short
    lines such as "}", "return L;" or "return false;", are not evidence;
  - links: every relative link of the kit's Markdown files points to a file
    or folder of the kit;
  - TODO lines: a PT_TODO(N) or PT_TODO_AS(N, ...) in stages/partK_*/ has
    N = K (the grader reads the part from the line a stub prints).
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
REFERENCE_ONLY = "// REFERENCE ONLY"
REFERENCE_ONLY_DOC = "<!-- REFERENCE ONLY"
# Left out of the kit: everything students do not get lives in the
# instructors' folder; CI runs on the reference tree only.
LEFT_OUT = (".ci/", "instructors/")
OVERLAY_DIR = "instructors/starter_kit/overlay"
# Overlay file (in OVERLAY_DIR) -> the kit file it becomes.
OVERLAY = {
    "README.md": "README.md",
    "grader_README.md": "grader/README.md",
    "run.sh": "scripts/run.sh",
    "stages_README.md": "stages/README.md",
}
GIVEN_HEADING = re.compile(r"^##\s+Given code\s*$")
WHOLE_FILE = "whole file"
# Shorter lines ("}", "return L;") and lines of fewer words ("return false;")
# prove nothing.
MIN_LEAK_LENGTH = 12
MIN_LEAK_WORDS = 3
SOURCE_EXTENSIONS = (".h", ".hpp", ".cpp", ".cc")
TODO_CALL = re.compile(r"\bPT_TODO(?:_AS)?\s*\(\s*(\d+)")
PART_FOLDER = re.compile(r"^stages/part(\d+)_")


class KitError(Exception):
    pass


# ---------------------------------------------------------------- markers


def strip_regions(path, lines):
    """Returns (kit lines, solution lines, regions) for one file; regions
    are (BEGIN line, END line) pairs, 1-based and inclusive."""
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
            out.extend(indent + s + "\n" for s in stubs)
            regions.append((begin_line, number))
            inside = False
            drop_blank = not stubs and bool(out) and not out[-1].strip()
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


# ------------------------------------------------- C++ definition scanner
#
# Not a C++ parser: a brace matcher that finds the definitions at namespace
# level (inside any number of named or anonymous namespaces and extern "C"
# blocks) of code whose comments, string and character literals and
# preprocessor lines have been blanked out. Member functions are part of
# their class; function bodies are skipped whole.

RAW_STRING = re.compile(r'(?:u8|[uUL])?R"([^()\\\s]{0,16})\(')
CLASS_HEAD = re.compile(r"^(?:(?:typedef|static|inline|constexpr|const|volatile|extern|export)\s+)*"
                        r"(struct|class|union|enum(?:\s+(?:class|struct))?)\b\s*((?:\w+\s*::\s*)*\w+)?")
NAMESPACE_HEAD = re.compile(r"^(?:inline\s+)?namespace(?:\s+[\w:\s]*)?$")
EXTERN_BLOCK = re.compile(r'^extern\s*"\s*"$')
IDENT_BEFORE = re.compile(r"((?:~?\w+\s*(?:<[^<>;{}]*>)?\s*::\s*)*~?\w+)\s*(?:<[^<>;{}]*>)?\s*$")
OPERATOR_NAME = re.compile(r"((?:\w+\s*::\s*)*operator\s*(?:\(\s*\)|\[\s*\]|[^\s(]+|\s\w+))")
SKIPPED_STATEMENTS = re.compile(r"^(?:static_assert|using\s+namespace|namespace|friend|extern\s+template|template\s+"
                                r"(?:class|struct)|_Static_assert)\b")


def blank_literals(text):
    """Comments, string and character literals blanked with spaces; newlines
    and every other character kept in place, so offsets and lines hold."""
    out = list(text)
    n = len(text)

    def blank(a, b):
        for k in range(a, min(b, n)):
            if out[k] != "\n":
                out[k] = " "

    i = 0
    while i < n:
        c = text[i]
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
            continue
        if c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            blank(i, j)
            i = j
            continue
        if c in "uULR" and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = RAW_STRING.match(text, i)
            if m:
                close = text.find(")" + m.group(1) + '"', m.end())
                close = n if close < 0 else close
                blank(m.end(), close)
                i = close + len(m.group(1)) + 2
                continue
        if c == '"' or c == "'":
            if c == "'":
                # A digit separator (1'000'000) is not a character literal.
                k = i - 1
                while k >= 0 and (text[k].isalnum() or text[k] in "_."):
                    k -= 1
                if k + 1 < i and text[k + 1].isdigit():
                    i += 1
                    continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            blank(i + 1, j)
            i = j + 1
            continue
        i += 1
    return "".join(out)


def without_preprocessor(text):
    """Blanked code without its preprocessor lines. Every branch of an #if
    is kept, except when the branches open or close braces unevenly
    (#if A / f(int) { / #else / f(long) { / #endif): then only the first
    branch of that #if is kept, as the braces of the others repeat it."""
    lines = text.split("\n")
    directive = [False] * len(lines)
    continued = False
    for k, line in enumerate(lines):
        directive[k] = continued or line.lstrip().startswith("#")
        continued = directive[k] and line.rstrip().endswith("\\")
    stack, groups = [], []  # a group: its branches' [first, last] content lines
    for k, line in enumerate(lines):
        if not directive[k] or (k > 0 and directive[k - 1] and lines[k - 1].rstrip().endswith("\\")):
            continue
        word = re.match(r"\s*#\s*(\w*)", line).group(1)
        if word in ("if", "ifdef", "ifndef"):
            stack.append([[k + 1, None]])
        elif word in ("elif", "else") and stack:
            stack[-1][-1][1] = k - 1
            stack[-1].append([k + 1, None])
        elif word == "endif" and stack:
            stack[-1][-1][1] = k - 1
            groups.append(stack.pop())
    kept = [not d for d in directive]
    for branches in groups:
        balance = [sum(lines[j].count("{") - lines[j].count("}") for j in range(a, b + 1) if not directive[j])
                   for a, b in branches]
        if any(balance):
            for a, b in branches[1:]:
                for j in range(a, b + 1):
                    kept[j] = False
    return "\n".join(line if keep else "" for line, keep in zip(lines, kept))


class Definition:
    def __init__(self, name, kind, first_line, last_line):
        self.name, self.kind, self.first_line, self.last_line = name, kind, first_line, last_line


def match_close(text, i, path, line_of):
    """Index of the bracket closing the one at text[i]."""
    pairs = {"{": "}", "(": ")", "[": "]"}
    stack = [pairs[text[i]]]
    j = i + 1
    n = len(text)
    while j < n:
        c = text[j]
        if c in pairs:
            stack.append(pairs[c])
        elif c in ")]}":
            if c != stack.pop():
                raise KitError(f"{path}:{line_of(j)}: unmatched '{c}'")
            if not stack:
                return j
        j += 1
    raise KitError(f"{path}:{line_of(i)}: '{text[i]}' never closed")


def top_level(text, chars):
    """Offsets of the characters of `chars` outside (), [], {} and <>."""
    found, depth, angle = [], 0, 0
    for k, c in enumerate(text):
        if depth == 0 and angle == 0 and c in chars:
            found.append(k)
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif depth == 0 and c == "<" and text[k + 1:k + 2] != "<" and text[k - 1:k] != "<":
            angle += 1
        elif depth == 0 and c == ">" and angle > 0 and text[k - 1:k] != "-":
            angle -= 1
    return found


def plain_assignment(head):
    """Offset of the first top-level '=' that is an initializer, or -1."""
    for k in top_level(head, "="):
        if head[k + 1:k + 2] == "=" or head[k - 1:k] in ("=", "!", "<", ">"):
            continue
        return k
    return -1


def close_paren(text, k):
    """Offset just past the ')' closing the '(' at text[k] (or the end)."""
    depth = 0
    for j in range(k, len(text)):
        depth += {"(": 1, ")": -1}.get(text[j], 0)
        if depth == 0:
            return j + 1
    return len(text)


def clean_head(head):
    """The head of a declaration without template headers and attributes."""
    head = re.sub(r"\[\[.*?\]\]", " ", head, flags=re.S)
    while True:
        m = re.search(r"\b(?:alignas|__attribute__|__declspec)\s*(?=\()", head)
        if not m:
            break
        head = head[:m.start()] + " " + head[close_paren(head, m.end()):]
    while True:
        m = re.match(r"\s*template\s*<", head)
        if not m:
            break
        depth, k = 1, m.end()
        while k < len(head) and depth:
            depth += {"<": 1, ">": -1}.get(head[k], 0)
            k += 1
        head = head[k:]
    return " ".join(head.split())


def function_name(head):
    if re.search(r"\boperator\b", head):
        m = OPERATOR_NAME.search(head)
        return re.sub(r"\s+", "", m.group(1)) if m else "operator"
    parens = top_level(head, "(")
    prefix = head[:parens[0]] if parens else head
    m = IDENT_BEFORE.search(prefix)
    if not m:
        return None
    name = re.sub(r"<[^<>]*>", "", m.group(1))  # foo<int> -> foo
    return re.sub(r"\s+", "", name)


def variable_name(head_before_eq):
    text = re.sub(r"\[[^\]]*\]\s*$", "", head_before_eq.rstrip())
    m = re.search(r"((?:\w+\s*::\s*)*\w+)\s*$", text)
    return re.sub(r"\s+", "", m.group(1)) if m else None


def has_initializer_list(head):
    """Whether a function head ends in a constructor's initializer list."""
    parens = top_level(head, "(")
    if not parens:
        return False
    rest = head[close_paren(head, parens[0]):]
    return bool(re.match(r"\s*(?:noexcept\s*(?:\([^()]*\))?\s*)?:(?!:)", rest))


def classify(head, has_body):
    """(kind, name) of a namespace-level declaration, or None when it
    defines nothing (a declaration, static_assert, using namespace, ...)."""
    h = clean_head(head)
    if not h or SKIPPED_STATEMENTS.match(h):
        return None
    m = CLASS_HEAD.match(h)
    if m and has_body and not top_level(h[m.end():], "("):
        return (m.group(1).split()[0], re.sub(r"\s+", "", m.group(2) or ""))
    if re.match(r"typedef\b", h):
        return ("alias", variable_name(h)) if not has_body else None
    eq = plain_assignment(h)
    if eq >= 0 and not re.search(r"\boperator\b", h[:eq]):
        if h.startswith("using "):
            return ("alias", variable_name(h[len("using "):eq]))
        if re.fullmatch(r"\s*(?:default|delete)\s*", h[eq + 1:]):
            return ("function", function_name(h[:eq]))
        return ("constant" if re.search(r"\b(?:const|constexpr)\b", h[:eq]) else "variable", variable_name(h[:eq]))
    if top_level(h, "("):
        return ("function", function_name(h)) if has_body else None
    if has_body:  # Type name{...};
        return ("variable", variable_name(h))
    return None


def scan_definitions(path, view):
    """Namespace-level definitions of one blanked view of a file."""
    line_starts = [0] + [k + 1 for k, c in enumerate(view) if c == "\n"]

    def line_of(offset):
        lo, hi = 0, len(line_starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if line_starts[mid] <= offset:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    defs, namespaces = [], 0
    n = len(view)
    start = 0  # where the current statement began
    i = 0

    def statement_line(a):
        while a < n and view[a].isspace():
            a += 1
        return line_of(a)

    def end_of_statement(k):
        """Offset of the ';' ending the statement that continues at k."""
        while k < n:
            c = view[k]
            if c in "([{":
                k = match_close(view, k, path, line_of)
            elif c == ";":
                return k
            elif c in ")]}":
                raise KitError(f"{path}:{line_of(k)}: unmatched '{c}'")
            k += 1
        raise KitError(f"{path}:{line_of(start)}: statement never ends (missing ';')")

    while i < n:
        c = view[i]
        if c in "([":
            i = match_close(view, i, path, line_of) + 1
            continue
        if c == ";":
            kind = classify(view[start:i], has_body=False)
            if kind and kind[1]:
                defs.append(Definition(kind[1], kind[0], statement_line(start), line_of(i)))
            start = i + 1
        elif c == "{":
            head = clean_head(view[start:i])
            if NAMESPACE_HEAD.match(head) or EXTERN_BLOCK.match(head):
                namespaces += 1
                start = i + 1
            else:
                kind = classify(view[start:i], has_body=True)
                close = match_close(view, i, path, line_of)
                if kind and kind[0] == "function" and has_initializer_list(head):
                    # A constructor's initializer list: brace initializers
                    # follow a name; the body follows ')' or '}'.
                    while True:
                        before = view[:i].rstrip()[-1:]
                        if not (before.isalnum() or before in "_>"):
                            break
                        k = close + 1
                        while k < n and view[k] not in "{;":
                            if view[k] in "([":
                                k = match_close(view, k, path, line_of)
                            k += 1
                        if k >= n or view[k] != "{":
                            break
                        i, close = k, match_close(view, k, path, line_of)
                last = close
                if kind and kind[0] != "function":
                    last = end_of_statement(close + 1)
                if kind and not kind[1] and kind[0] in ("struct", "class", "union", "enum"):
                    declarator = re.match(r"\s*((?:\w+\s*)+)", view[close + 1:last])
                    kind = (kind[0], declarator.group(1).split()[-1] if declarator else "")
                if kind:
                    defs.append(Definition(kind[1] or f"<anonymous {kind[0]}>", kind[0], statement_line(start),
                                           line_of(last)))
                i = last + 1
                start = i
                continue
        elif c in ")]":
            raise KitError(f"{path}:{line_of(i)}: unmatched '{c}'")
        elif c == "}":
            if namespaces == 0:
                raise KitError(f"{path}:{line_of(i)}: unmatched '}}'")
            namespaces -= 1
            start = i + 1
        i += 1
    if namespaces:
        raise KitError(f"{path}: a namespace is never closed")
    if view[start:].strip():
        raise KitError(f"{path}:{statement_line(start)}: statement never ends (missing ';')")
    return defs


def definitions(path, text):
    """The namespace-level definitions of a C++ file."""
    return scan_definitions(path, without_preprocessor(blank_literals(text)))


# ------------------------------------------------------ the given-code lists


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


# ------------------------------------------------------------ other checks


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


# ------------------------------------------------------------------- files


def listed_files(root):
    files = None
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], check=True,
                             capture_output=True).stdout.decode().strip()
        if os.path.realpath(top) == os.path.realpath(root):
            listed = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                                     "--exclude-standard"], check=True, capture_output=True).stdout
            files = sorted({f for f in listed.decode().split("\0") if f})
    except (OSError, subprocess.CalledProcessError):
        pass
    if files is None:
        files = []
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = [d for d in dirnames
                           if d != ".git" and not (dirpath == root and d.startswith("build"))]
            files += [os.path.relpath(os.path.join(dirpath, f), root) for f in filenames]
    return sorted(f for f in files if os.path.isfile(os.path.join(root, f)))


def is_text(path):
    return path.endswith(SOURCE_EXTENSIONS + (".txt", ".cmake", ".md", ".sh", ".py"))


def is_source(path):
    # Only C++ sources carry solution regions; documents show the markers
    # as examples and are copied unchanged.
    return path.endswith(SOURCE_EXTENSIONS)


def make_kit(root):
    """{kit path: lines, or None to copy the file as is} and {kit path:
    source path}, after every check."""
    files = listed_files(root)
    kit, origin = {}, {}
    solution_lines, outside_lines = set(), set()
    stage_sources, left_out, regions_stubbed = {}, [], 0
    for rel in files:
        if rel.startswith(LEFT_OUT):
            continue
        src = os.path.join(root, rel)
        if not is_text(rel):
            kit[rel], origin[rel] = None, src  # copied as is
            continue
        with open(src, encoding="utf-8") as f:
            lines = f.readlines()
        if is_source(rel) and lines and lines[0].startswith(REFERENCE_ONLY):
            left_out.append(rel)
            solution_lines.update(l.strip() for l in lines)
            continue
        if rel.endswith(".md") and lines and lines[0].startswith(REFERENCE_ONLY_DOC):
            continue  # check_links stops any kit document that links to it
        if is_source(rel):
            check_todo_parts(rel, lines)
            out, solution, regions = strip_regions(rel, lines)
            if regions:
                out = mark_empty_helper_namespaces(out)
            regions_stubbed += len(regions)
            if rel.startswith("stages/"):
                stage_sources[rel] = ("".join(lines), regions)
        else:
            out, solution = lines, []
        kit[rel], origin[rel] = out, src
        solution_lines.update(l.strip() for l in solution)
        outside_lines.update(l.strip() for l in out)

    check_given_code(root, stage_sources)
    check_left_out_references(kit, left_out)

    overlay = os.path.join(root, OVERLAY_DIR)
    if os.path.isdir(overlay):
        for name in sorted(os.listdir(overlay)):
            if name not in OVERLAY:
                raise KitError(f"{OVERLAY_DIR}/{name}: not an overlay file the generator knows (OVERLAY)")
        for name, target in sorted(OVERLAY.items()):
            src = os.path.join(overlay, name)
            if not os.path.isfile(src):
                raise KitError(f"{OVERLAY_DIR}/{name}: overlay file missing")
            with open(src, encoding="utf-8") as f:
                kit[target], origin[target] = f.readlines(), src

    check_leaks(kit, solution_lines, outside_lines)
    check_links(kit)
    return kit, origin, left_out, regions_stubbed


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(sys.argv) == 2 else 1
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    dest = os.path.abspath(sys.argv[1])
    if dest == root or dest.startswith(root + os.sep) and not dest.startswith(os.path.join(root, "build")):
        print(f"make_starter_kit: error: {dest}: choose a folder outside the repository (or under build/)",
              file=sys.stderr)
        return 1
    if os.path.exists(dest) and os.listdir(dest):
        print(f"make_starter_kit: error: {dest}: folder exists and is not empty", file=sys.stderr)
        return 1

    try:
        kit, origin, left_out, regions = make_kit(root)
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
          + (f" (left out as reference-only: {', '.join(left_out)})" if left_out else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
