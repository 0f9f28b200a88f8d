#!/usr/bin/env python3
"""Scores the grader's hints on the held-out bugs of held_out.txt, from the
folders grade_held_out.sh graded (BUILD_ROOT/<name>.grade): for each bug the
grader caught, the "Likely cause" lines `grader hints --graded` gives its
folder (as report.txt would), and whether the first names the bug's
function, whether one of the first three does, and the same for its part.
Rates for Project 3-1 and 3-2 apart (held_out.txt's headings).

    score_held_out.py BUILD_ROOT [--grader BIN] [--catalogue FILE] [--table FILE]

Exits 1 naming the problem when a folder is not a grading run's; a bug not
graded is listed as such.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
HINT = re.compile(r"^Likely cause \d+ of \d+: .*\((\S+) in (stages/part(\d)_\S*)")


def read_list(path):
    """The bugs, each with its project: that of the "# Project 3-x" heading
    above it (a bug of part 4's loop that only mirrors and glass show is
    Project 3-2's), else its part's."""
    bugs = []
    heading = None
    for number, line in enumerate(open(path), 1):
        line = line.strip()
        m = re.match(r"#\s*Project (3-[12])\b", line)
        if m:
            heading = m.group(1)
        if not line or line.startswith("#"):
            continue
        fields = line.split(None, 3)
        if len(fields) < 4 or not fields[1].isdigit():
            sys.exit(f"{path}:{number}: expected 'name part function description'")
        part = int(fields[1])
        bugs.append({"name": fields[0], "part": part, "function": fields[2],
                     "project": heading or ("3-1" if part <= 5 else "3-2")})
    return bugs


def caught(grade_dir):
    path = os.path.join(grade_dir, "results.json")
    try:
        r = json.load(open(path))
    except (OSError, ValueError) as e:
        sys.exit(f"{path}: not a grading run's results ({e})")
    return any(t["score"] < t["max_score"] for t in r["tests"])


def hints(grader, catalogue, grade_dir):
    cmd = [grader, "hints", "--graded", grade_dir]
    if catalogue:
        cmd += ["--catalogue", catalogue]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 1):
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()}")
    named = []
    for line in p.stdout.splitlines():
        m = HINT.match(line)
        if m:
            named.append((m.group(1), int(m.group(3))))
    return named


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build_root")
    ap.add_argument("--grader", default=os.path.join(ROOT, "build", "bin", "grader"))
    ap.add_argument("--catalogue", default=None, help="the grader's own when not given")
    ap.add_argument("--table", default=None)
    a = ap.parse_args()
    rows, totals = [], {}
    for bug in read_list(os.path.join(HERE, "held_out.txt")):
        d = os.path.join(a.build_root, bug["name"] + ".grade")
        project = bug["project"]
        if not os.path.isdir(os.path.join(d, "cases")):
            rows.append(f"| {bug['name']} | {bug['part']} | {bug['function']} | not graded | | | |")
            continue
        if not caught(d):
            rows.append(f"| {bug['name']} | {bug['part']} | {bug['function']} | not caught | | | |")
            continue
        named = hints(a.grader, a.catalogue, d)[:3]
        first = bool(named) and named[0][0] == bug["function"]
        top3 = any(f == bug["function"] for f, _ in named)
        part_first = bool(named) and named[0][1] == bug["part"]
        part_top3 = any(p == bug["part"] for _, p in named)
        t = totals.setdefault(project, [0, 0, 0, 0, 0])
        for i, ok in enumerate((True, first, top3, part_first, part_top3)):
            t[i] += ok
        yes = lambda b: "yes" if b else "no"
        rows.append(f"| {bug['name']} | {bug['part']} | {bug['function']} | "
                    f"{', '.join(f for f, _ in named) or 'none close'} | {yes(first)} | {yes(top3)} | "
                    f"{yes(part_first)} / {yes(part_top3)} |")
    lines = ["| bug | part | function | hints, first to third | right function first | in the first three | "
             "right part first / in the first three |", "|---|---:|---|---|---|---|---|"] + rows + [""]
    for project in ("3-1", "3-2"):
        n, first, top3, pf, p3 = totals.get(project, [0] * 5)
        pct = lambda k: f"{k} of {n} ({100 * k / n:.0f} %)" if n else "none"
        lines.append(f"Project {project}, {n} caught: right function first {pct(first)}, in the first three "
                     f"{pct(top3)}; right part first {pct(pf)}, in the first three {pct(p3)}.")
    text = "\n".join(lines) + "\n"
    if a.table:
        stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip() or "unknown"
        head = ("<!-- REFERENCE ONLY: measured on held-out bugs; the starter kit leaves this table out -->\n"
                "# Hints on bugs the catalogue was not made from\n\n"
                "Each bug of [held_out.txt](held_out.txt) is graded as any submission (on the cases of its part "
                "and the later ones) and its first three \"Likely cause\" lines are read; none of these bugs is "
                "in the catalogue of known bugs (`grader/known_bugs.json`). Goals: the right function first for "
                "at least 80 %, among the first three for at least 90 %.\n\n"
                f"Scored by `instructors/mutants/held_out/score_held_out.py` at commit {commit} on {stamp}.\n\n")
        tmp = a.table + ".tmp"
        open(tmp, "w").write(head + text)
        os.replace(tmp, a.table)
    print(text, end="")


if __name__ == "__main__":
    main()
