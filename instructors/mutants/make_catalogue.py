#!/usr/bin/env python3
"""Makes the grader's catalogue of known bugs, grader/known_bugs.json, from the
mutants' grading results: for every mutant of mutants.txt with a line in
hints.txt, where the bug lives, its hint, and its signature on every case it
loses points on (cases/<case>/result.json of its grading run).

    instructors/mutants/make_catalogue.py BUILD_ROOT [--commit C] [--out FILE] [--update] [--probes FILE]

BUILD_ROOT is grade_mutants.sh's --build-root (build/mutants by default),
which holds <mutant>.grade/ for every mutant graded; grade_mutants.sh runs
this at its end. With --update, a mutant without a folder in BUILD_ROOT keeps
its signature from the catalogue already at --out (its hint is taken from
hints.txt again): for adding a newly graded mutant without grading them all
again; the catalogue's commit then names both gradings. Exits 1 naming the
problem when a mutant has no hint, a hint names no mutant, or a mutant's
results are missing (with --update: and it is not in the catalogue either).

--probes FILE (default instructors/mutants/probes.json, made by
instructors/check_functions.sh mutants; ignored when absent): which functions
each mutant's build answers the function checks differently from the
reference's. Each bug gets "probes_disagree" and the catalogue
"probed_functions", so that the hints' leave-one-out measure can use each
bug's own answers, as a graded build's report does.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def read_mutants(path):
    parts = {}
    for line in open(path):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        name, part = line.split()[:2]
        parts[name] = int(part)
    return parts


def read_hints(path):
    hints = {}
    for number, line in enumerate(open(path), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f.strip() for f in line.split("|")]
        if len(fields) != 5 or not all(fields):
            sys.exit(f"{path}:{number}: expected 'name | function | file | README section | hint'")
        name, function, file, readme, hint = fields
        if name in hints:
            sys.exit(f"{path}:{number}: {name} twice")
        hints[name] = {"function": function, "file": file, "readme": readme, "hint": hint}
    return hints


def case_results(grade_dir):
    cases = {}
    folder = os.path.join(grade_dir, "cases")
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name, "result.json")
        if os.path.exists(path):
            cases[name] = json.load(open(path))
    return cases


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build_root")
    ap.add_argument("--commit", default=None)
    ap.add_argument("--out", default=os.path.join(ROOT, "grader", "known_bugs.json"))
    ap.add_argument("--probes", default=os.path.join(HERE, "probes.json"))
    ap.add_argument("--update", action="store_true",
                    help="keep the signatures of --out's catalogue for the mutants BUILD_ROOT has not graded")
    a = ap.parse_args()
    old = {}
    old_commit = None
    if a.update:
        try:
            previous = json.load(open(a.out))
            old = {b["name"]: b for b in previous["bugs"]}
            old_commit = previous.get("commit")
        except (OSError, ValueError, KeyError) as e:
            sys.exit(f"{a.out}: --update needs the catalogue to update ({e})")
    parts = read_mutants(os.path.join(HERE, "mutants.txt"))
    hints = read_hints(os.path.join(HERE, "hints.txt"))
    for name in parts:
        if name not in hints:
            sys.exit(f"hints.txt: no line for mutant {name}")
    for name in hints:
        if name not in parts:
            sys.exit(f"hints.txt: {name} is not a mutant of mutants.txt")
    commit = a.commit or subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                        text=True).stdout.strip() or "unknown"
    bugs = []
    graded_now = []
    for name, part in parts.items():
        grade_dir = os.path.join(a.build_root, name + ".grade")
        if not os.path.isdir(os.path.join(grade_dir, "cases")):
            if name in old:
                bug = {"name": name, "part": part}
                bug.update(hints[name])
                bug["cases"] = old[name]["cases"]
                bugs.append(bug)
                continue
            sys.exit(f"{grade_dir}: no grading results for mutant {name} (run grade_mutants.sh first)")
        graded_now.append(name)
        cases = {}
        for case, r in case_results(grade_dir).items():
            # Only the cases it loses points on: a passed case is neutral.
            if r["verdict"] == "passed" and r["score"] >= r["max_score"]:
                continue
            figures = {k: round(v, 4) for k, v in sorted(r.get("signature", {}).items()) if v is not None}
            cases[case] = {"failed": True, "signature": figures}
        bug = {"name": name, "part": part}
        bug.update(hints[name])
        bug["cases"] = cases
        bugs.append(bug)
    probed = None
    if a.probes and os.path.exists(a.probes):
        pj = json.load(open(a.probes))
        probed = pj["probed_functions"]
        for bug in bugs:
            if bug["name"] in pj["bugs"]:
                bug["probes_disagree"] = pj["bugs"][bug["name"]]
    if a.update and old_commit:
        commit = f"{old_commit}; {', '.join(graded_now) or 'none'} at {commit}"
    out = {
        "about": "Known bugs (the grader's mutants) and their signatures, for the report's hints. Made by "
                 "instructors/mutants/make_catalogue.py from grade_mutants.sh's results; do not edit.",
        "commit": commit,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "bugs": bugs,
    }
    if probed is not None:
        out["probed_functions"] = probed
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        f.write("{\n")
        for key in ("about", "commit", "date", "probed_functions"):
            if key in out:
                f.write(f'  {json.dumps(key)}: {json.dumps(out[key])},\n')
        f.write('  "bugs": [\n')
        for i, b in enumerate(bugs):
            head = {k: v for k, v in b.items() if k != "cases"}
            f.write("    {" + json.dumps(head)[1:-1] + ', "cases": {\n')
            items = list(b["cases"].items())
            for j, (case, c) in enumerate(items):
                f.write(f'      {json.dumps(case)}: {json.dumps(c)}' + ("," if j + 1 < len(items) else "") + "\n")
            f.write("    }}" + ("," if i + 1 < len(bugs) else "") + "\n")
        f.write("  ]\n}\n")
    os.replace(tmp, a.out)
    print(f"make_catalogue.py: {len(bugs)} known bugs -> {os.path.relpath(a.out, ROOT)} (commit {commit})")


if __name__ == "__main__":
    main()
