"""The C++ definition scanner.

Not a C++ parser: a brace matcher that finds the definitions at namespace
level (inside any number of named or anonymous namespaces and extern "C"
blocks) of code whose comments, string and character literals and
preprocessor lines have been blanked out. Member functions are part of
their class; function bodies are skipped whole.
"""
import re

from kitgen.base import KitError
from kitgen.cpp_text import blank_literals, without_preprocessor


CLASS_HEAD = re.compile(r"^(?:(?:typedef|static|inline|constexpr|const|volatile|extern|export)\s+)*"
                        r"(struct|class|union|enum(?:\s+(?:class|struct))?)\b\s*((?:\w+\s*::\s*)*\w+)?")
NAMESPACE_HEAD = re.compile(r"^(?:inline\s+)?namespace(?:\s+[\w:\s]*)?$")
EXTERN_BLOCK = re.compile(r'^extern\s*"\s*"$')
IDENT_BEFORE = re.compile(r"((?:~?\w+\s*(?:<[^<>;{}]*>)?\s*::\s*)*~?\w+)\s*(?:<[^<>;{}]*>)?\s*$")
OPERATOR_NAME = re.compile(r"((?:\w+\s*::\s*)*operator\s*(?:\(\s*\)|\[\s*\]|[^\s(]+|\s\w+))")
SKIPPED_STATEMENTS = re.compile(r"^(?:static_assert|using\s+namespace|namespace|friend|extern\s+template|template\s+"
                                r"(?:class|struct)|_Static_assert)\b")


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
