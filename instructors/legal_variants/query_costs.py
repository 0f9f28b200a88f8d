#!/usr/bin/env python3
"""The ray-query costs of several builds on every case from part 2 on.

Renders each case of grader/cases.txt with part >= 2 (the exact command
`grader compare --list` prints, -t 1, with --stats-json) with each build at
each seed, and takes per build and case the median over the seeds of the
figures the grader's cost checks read (grader/src/checks.cpp):
  closest_tests_per_query  (primitive_tests - shadow_primitive_tests) / closest_queries
  shadow_tests_per_query   shadow_primitive_tests / shadow_queries (0 without shadow rays)
  shadow_per_query         shadow_queries / closest_queries
  tests_per_ray            primitive_tests / (closest_queries + shadow_queries)
Prints one table per figure: the reference's (reference_images/<case>/meta.json)
and each build's, with its ratio to the reference's. With --out, writes for
each case the larger over the --baseline builds of each figure (what a plain
binary BVH achieves there), with every build's own figures beside it.

  query_costs.py --build NAME=PATH [--build ...] [--baseline NAME,NAME] [--out FILE]
                 [--seeds 1,2,3] [-j 2] [--work DIR] [--commit C]
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import shlex
import statistics
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
FIGURES = ["closest_tests_per_query", "shadow_tests_per_query", "shadow_per_query", "tests_per_ray"]


def cases_from_part(part, case_list):
    """Names of the cases of `case_list` with part >= `part`, in order."""
    names = []
    for line in open(case_list):
        words = line.split()
        if words and not words[0].startswith("#") and int(words[1]) >= part:
            names.append(words[0])
    return names


def case_commands(grader, case_list):
    out = subprocess.run([grader, "compare", "--list", "--cases", case_list], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    cmds = {}
    for line in out.splitlines():
        words = line.split()
        if len(words) > 2 and words[1].endswith("pathtracer"):
            cmds[words[0]] = shlex.split(line)[2:]
    return cmds


def without_outputs(args):
    """The case's arguments without --seed, -f and --pfm."""
    a = list(args)
    for flag in ("--seed", "-f", "--pfm"):
        i = a.index(flag)
        del a[i : i + 2]
    return a


def render_stats(binary, args, seed, stem):
    a = without_outputs(args)
    a[-1:-1] = ["--seed", str(seed), "-f", stem + ".png", "--stats-json", stem + ".json", "-t", "1", "--no-progress"]
    r = subprocess.run([binary] + a, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{binary} {' '.join(a)}: exit {r.returncode}: {r.stderr.strip()[-300:]}")
    return json.load(open(stem + ".json"))


def figures(stats):
    closest = stats["closest_queries"]
    shadow = stats["shadow_queries"]
    tests = stats["primitive_tests"]
    shadow_tests = stats["shadow_primitive_tests"]
    rays = closest + shadow
    return {
        "closest_tests_per_query": (tests - shadow_tests) / closest if closest > 0 else 0.0,
        "shadow_tests_per_query": shadow_tests / shadow if shadow > 0 else 0.0,
        "shadow_per_query": shadow / closest if closest > 0 else 0.0,
        "tests_per_ray": tests / rays if rays > 0 else 0.0,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", action="append", required=True, help="NAME=PATH of a pathtracer")
    ap.add_argument("--baseline", default="", help="builds (comma-separated) whose larger figure --out records")
    ap.add_argument("--out", help="the JSON file of the baseline's figures")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--cases", default=os.path.join(ROOT, "grader", "cases.txt"),
                    help="the case list (instructors/hidden_cases/cases.txt for the hidden cases)")
    ap.add_argument("--references", default=os.path.join(ROOT, "reference_images"),
                    help="the cases' references (for the comparison tables)")
    ap.add_argument("-j", type=int, default=2)
    ap.add_argument("--grader", default=os.path.join(ROOT, "build", "bin", "grader"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "plain_bvh", "renders"))
    ap.add_argument("--commit", default="unknown", help="the commit the builds were made from, for --out")
    a = ap.parse_args()
    builds = []
    for b in a.build:
        name, sep, path = b.partition("=")
        if not sep or not os.access(path, os.X_OK):
            ap.error(f"--build {b}: want NAME=PATH of an executable")
        builds.append((name, os.path.abspath(path)))
    names = [n for n, _ in builds]
    baseline = [n for n in a.baseline.split(",") if n]
    for n in baseline:
        if n not in names:
            ap.error(f"--baseline {n}: not one of the --build names")
    if a.out and not baseline:
        ap.error("--out needs --baseline")
    try:
        seeds = [int(s) for s in a.seeds.split(",")]
    except ValueError:
        ap.error(f"--seeds {a.seeds}: want integers separated by commas")
    case_list = os.path.abspath(a.cases)
    cmds = case_commands(a.grader, case_list)
    cases = cases_from_part(2, case_list)
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")

    # per[name][case] = {figure: median over seeds}
    per = {n: {} for n in names}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.j) as pool:
        jobs = {}
        for name, binary in builds:
            for case in cases:
                d = os.path.join(a.work, name, case)
                os.makedirs(d, exist_ok=True)
                jobs[(name, case)] = [pool.submit(render_stats, binary, cmds[case], s, os.path.join(d, f"s{s}"))
                                      for s in seeds]
        for (name, case), futs in jobs.items():
            runs = [figures(f.result()) for f in futs]
            per[name][case] = {k: statistics.median(r[k] for r in runs) for k in FIGURES}
            print(f"{name:24s} {case:22s} " + ", ".join(f"{k} {per[name][case][k]:.3f}" for k in FIGURES),
                  file=sys.stderr, flush=True)

    ref = {c: json.load(open(os.path.join(a.references, c, "meta.json"))) for c in cases}
    for k in FIGURES:
        print(f"\n{k} (median over seeds {a.seeds}; x = ratio to the reference's)\n")
        print("| case | reference | " + " | ".join(names) + " |")
        print("|---|---:|" + "---:|" * len(names))
        for c in cases:
            r = ref[c].get(k, 0.0)
            cells = []
            for n in names:
                v = per[n][c][k]
                cells.append(f"{v:.2f} ({v / r:.1f}x)" if r > 0 else f"{v:.2f}")
            print(f"| {c} | {r:.2f} | " + " | ".join(cells) + " |")

    if a.out:
        out = {
            "what": "per case, the larger over the builds of the median over the seeds of each ray-query cost of "
                    "a plain binary BVH built the way the course suggests (what part 2's cost check compares "
                    "a student's BVH with)",
            "made_by": "measure_plain_bvh.sh (the instructors' tools, not in the starter kit)",
            "commit": a.commit,
            "date": started,
            "builds": baseline,
            "seeds": seeds,
            "cases": {},
        }
        for c in cases:
            entry = {k: round(max(per[n][c][k] for n in baseline), 6) for k in FIGURES}
            entry["command"] = "pathtracer " + " ".join(without_outputs(cmds[c]))
            entry["by_build"] = {n: {k: round(per[n][c][k], 6) for k in FIGURES} for n in baseline}
            out["cases"][c] = entry
        tmp = a.out + ".tmp"
        with open(tmp, "w") as f:
            json.dump(out, f, indent=2, sort_keys=True)
            f.write("\n")
        os.replace(tmp, a.out)
        print(f"\nWrote {os.path.relpath(a.out, ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
