"""What every module of the generator shares: the repository root, the
program's name in messages, the bad-input error, and path and time
formatting."""

import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROG = "make_figures.py"


class InputError(Exception):
    """Bad input: reported as one line, exit status 2."""


def display_path(path):
    """A path as shown to people: relative to the repository root when inside it."""
    a = os.path.abspath(path)
    rel = os.path.relpath(a, ROOT)
    return a if rel.startswith("..") else rel


def fmt_duration(s):
    s = int(round(s))
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{(s % 3600) // 60:02d}m"


def write_atomically(path, text):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
