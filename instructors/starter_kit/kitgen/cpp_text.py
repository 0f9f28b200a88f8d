"""C++ text made ready for the definition scanner: comments, string and
character literals blanked, preprocessor lines removed, offsets and lines
kept.
"""
import re


RAW_STRING = re.compile(r'(?:u8|[uUL])?R"([^()\\\s]{0,16})\(')


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
