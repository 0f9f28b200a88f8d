"""Checking a finished render: the TODO lines of its console log, and whether
its image is all black, as the renderer reports it (max_radiance in its
--stats-json). A starter-kit build prints a TODO line the first time it
reaches a function not written yet and keeps rendering, so a render that
exits 0 can still be a black or wrong figure."""

import html
import json
import os
import re

TODO_LINE = re.compile(r"(?<![A-Za-z0-9_])TODO:")


def todo_lines(log_path):
    """The distinct 'TODO: ...' lines of a render's log, in order."""
    try:
        with open(log_path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
    except OSError:
        return []
    out = []
    for line in text.splitlines():
        m = TODO_LINE.search(line)
        if m:
            line = line[m.start():].strip()
            if line not in out:
                out.append(line)
    return out


def max_radiance(stats):
    """The render's largest finite radiance channel before tone mapping, from its
    --stats-json (a dict); ValueError when it does not hold one."""
    v = stats.get("max_radiance") if isinstance(stats, dict) else None
    if v is None:
        raise ValueError("the renderer's --stats-json has no max_radiance (a pathtracer built before "
                         "the field existed?)")
    if isinstance(v, bool) or not isinstance(v, (int, float)) or v != v:
        raise ValueError(f"the renderer's --stats-json gives max_radiance {v!r}, not a number")
    return float(v)


def make_checks(log_path, stats):
    """What a finished render's log and figures say about it: its TODO lines,
    its max_radiance, whether its image is all black (no radiance above 0),
    and why the image could not be checked. Kept in the cache entry."""
    checks = {"todo": todo_lines(log_path), "max_radiance": None, "black": False, "image_error": None}
    try:
        checks["max_radiance"] = max_radiance(stats)
        checks["black"] = checks["max_radiance"] <= 0
    except ValueError as e:
        checks["image_error"] = str(e)
    return checks


def entry_checks(entry, stats=None):
    """make_checks() of a cache entry (its log.txt and render.json)."""
    if stats is None:
        try:
            with open(os.path.join(entry, "render.json")) as f:
                stats = json.load(f)
        except (OSError, ValueError):
            stats = None
    return make_checks(os.path.join(entry, "log.txt"), stats)


def current(checks):
    """Whether checks kept in a cache entry are of this kind (an entry made by an
    earlier generator, which decoded the PNG instead, is checked again)."""
    return isinstance(checks, dict) and "max_radiance" in checks and isinstance(checks.get("todo"), list)


def render_problems(r):
    """Why a finished figure needs a look, as (kind, text) pairs: "todo" (a line
    the renderer printed), "black" (every pixel 0, unless the recipe expects
    it), "image" (the image could not be checked). Empty for a good figure."""
    c = r.job.checks if r.job.status in ("ok", "cached") else None
    if not c:
        return []
    out = [("todo", line) for line in c.get("todo") or []]
    if c.get("black") and not r.expect_black:
        out.append(("black", "the image is all black (every pixel 0)"))
    elif (c.get("preview") or {}).get("flat") and not r.expect_black:
        color = c["preview"].get("color") or [0, 0, 0]
        out.append(("flat", "the preview shows nothing: every pixel is "
                    + ("black" if color == [0, 0, 0] else "the same colour, " + " ".join(map(str, color)))))
    if c.get("image_error"):
        out.append(("image", f"the image could not be checked: {c['image_error']}"))
    return out


def problem_text(kind, text):
    return f"the renderer printed '{text}'" if kind == "todo" else text


def problem_html(kind, text):
    if kind == "todo":
        return f"the renderer printed <code class=\"inline\">{html.escape(text)}</code>"
    return html.escape(text)


def problem_md(kind, text):
    text = text.replace("|", "\\|")
    return f"the renderer printed `{text}`" if kind == "todo" else text
