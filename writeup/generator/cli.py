"""The command line: options, the run from recipes to page, the messages on
stderr and the exit status (0 fine, 1 a render failed, 2 bad input, 3 a
figure flagged)."""

import argparse
import datetime
import os
import shlex
import shutil
import sys
import time

from .base import PROG, ROOT, InputError, display_path, fmt_duration
from .cache import Cache, FileHashes, cache_key, command_key
from .checks import problem_text, render_problems
from .flags import recipe_args
from .page import job_times, write_page
from .progress import Progress
from .recipes import Recipes
from .scheduler import Scheduler, cost_units, make_jobs


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog=PROG, description="Render the write-up's figures (cached, in parallel) and write an HTML and a "
                               "Markdown page.")
    ap.add_argument("--recipes", default=os.path.join(ROOT, "writeup", "figures.toml"),
                    help="figure recipes (default: writeup/figures.toml)")
    ap.add_argument("--pathtracer", default=os.path.join(ROOT, "build", "bin", "pathtracer"),
                    help="the pathtracer binary to render with (default: build/bin/pathtracer)")
    ap.add_argument("--out", help="output folder for index.html, index.md and img/ "
                                  "(default: writeup/out, with --quick writeup/out/quick)")
    ap.add_argument("--cache", help="render cache folder (default: OUT/cache)")
    ap.add_argument("-t", "--threads", type=int, default=os.cpu_count() or 1,
                    help="total threads for all renders running at once (default: the number of CPUs)")
    ap.add_argument("--quick", action="store_true",
                    help="render everything small (size and sample counts capped) for a check in minutes")
    ap.add_argument("--only", metavar="IDS",
                    help="comma-separated grid/table ids (shell patterns) to render and show; default all")
    ap.add_argument("--timeout", type=float, default=0,
                    help="kill a render after this many seconds and mark it failed (default: no limit)")
    ap.add_argument("--force", action="store_true", help="re-render everything, ignoring the cache")
    ap.add_argument("--dry-run", action="store_true",
                    help="list the renders and whether each is cached; render nothing, write nothing")
    ap.add_argument("--prune", action="store_true",
                    help="afterwards, delete cache entries that this page does not use")
    ap.add_argument("--no-progress", action="store_true", help="print nothing but errors and the summary")
    return ap.parse_args(argv)


def load_inputs(a):
    """The binary (absolute) and the recipes (--only applied); InputError for bad input."""
    if a.threads < 1:
        raise InputError("-t must be at least 1")
    binary = os.path.abspath(a.pathtracer)
    if not os.path.isfile(binary):
        raise InputError(f"pathtracer binary not found: {a.pathtracer} (build it with "
                         f"'cmake --build build --target pathtracer' or pass --pathtracer PATH)")
    if not os.access(binary, os.X_OK):
        raise InputError(f"pathtracer binary is not executable: {a.pathtracer}")
    recipes = Recipes(os.path.abspath(a.recipes), a.quick)
    if a.only:
        recipes.select(a.only)
    return binary, recipes


def to_render(jobs, cache, history, force):
    """The jobs the cache does not hold (all with force), each with its cost estimate:
    its recipe's time in the history, else the cost model's."""
    pending = []
    for j in jobs:
        if not force and cache.lookup(j):
            continue
        j.est = history.get(command_key(j.proto)) or cost_units(j.proto)
        pending.append(j)
    return pending


def dry_run(binary, renders):
    """--dry-run: each render's command and whether it is cached."""
    for r in renders:
        state = "cached" if r.job.status == "cached" else "to render"
        print(f"{state:9} {r.grid}/{r.name}: "
              f"{shlex.join([display_path(binary)] + recipe_args(r) + [display_path(r.scene)])}")


def copy_images(out_dir, renders):
    """The figures' images into OUT/img/<grid>/<name>.png (and the images shown
    beside them: <name>_rate.png, <name>_env_probability.png)."""
    img_dir = os.path.join(out_dir, "img")
    shutil.rmtree(img_dir, ignore_errors=True)
    for r in renders:
        j = r.job
        if j.status == "failed":
            continue
        os.makedirs(os.path.join(img_dir, r.grid), exist_ok=True)
        pairs = [("render.png", f"{r.name}.png")] + [(f, f"{r.name}{suffix}.png") for f, suffix, _ in r.side_images()]
        for src, dst in pairs:
            s = os.path.join(j.dir, src)
            if os.path.isfile(s):
                shutil.copyfile(s, os.path.join(img_dir, r.grid, dst))


def make_summary(binary, binary_hash, recipes, jobs, pending, failed, flagged, wall, budget):
    summary = {
        "binary": display_path(binary), "binary_sha256": binary_hash,
        "recipes": recipes.display, "quick": recipes.quick,
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "renders": len(recipes.renders), "distinct_renders": len(jobs),
        "rendered": len(pending), "cached": len(jobs) - len(pending), "failed": len(failed),
        "flagged": len(flagged), "wall_seconds": round(wall, 2), "thread_budget": budget,
    }
    wt, cpu = job_times(jobs)
    summary["wall_thread_seconds"] = round(wt, 1)
    summary["cpu_seconds"] = round(cpu, 1) if cpu is not None else None
    # Timing renders run alone; the rest share the thread budget.
    _, cpu_x = job_times([j for j in jobs if j.exclusive])
    summary["idle_estimate_seconds"] = (round(cpu_x + (cpu - cpu_x) / budget, 1)
                                        if cpu is not None and cpu_x is not None else None)
    return summary


def report(summary, failed, flagged, out_dir, wall):
    """One error line per failed render, one warning line per flagged figure, the summary line."""
    for j in failed:
        names = ", ".join(f"{r.grid}/{r.name}" for r in j.renders)
        sys.stderr.write(f"{PROG}: error: render {names} ({j.proto.where}) failed: {j.error}; "
                         f"log: {display_path(os.path.join(j.dir, 'log.txt'))}\n")
    for r, problems in flagged:
        sys.stderr.write(f"{PROG}: warning: figure {r.grid}/{r.name} ({r.where}) needs checking: "
                         + "; ".join(problem_text(k, t) for k, t in problems)
                         + f"; log: {display_path(os.path.join(r.job.dir, 'log.txt'))}\n")
    print(f"{PROG}: {summary['renders']} figures, {summary['distinct_renders']} distinct renders: "
          f"{summary['rendered']} rendered, {summary['cached']} cached, {summary['failed']} failed, "
          f"{summary['flagged']} figure(s) flagged, in {fmt_duration(wall)}; "
          f"page: {display_path(os.path.join(out_dir, 'index.html'))}")


def main(argv=None):
    a = parse_args(argv)
    try:
        binary, recipes = load_inputs(a)
    except InputError as e:
        sys.stderr.write(f"{PROG}: error: {e}\n")
        return 2

    out_dir = os.path.abspath(a.out or os.path.join(ROOT, "writeup", "out", "quick" if a.quick else ""))
    cache = Cache(os.path.abspath(a.cache) if a.cache else os.path.join(out_dir, "cache"))
    file_hash = FileHashes()
    binary_hash = file_hash(binary)
    jobs = make_jobs(recipes.renders, lambda r: cache_key(r, binary_hash, file_hash))
    history = cache.load_history()
    pending = to_render(jobs, cache, history, a.force)

    if a.dry_run:
        dry_run(binary, recipes.renders)
        return 0

    os.makedirs(cache.dir, exist_ok=True)
    run_binary = binary
    if pending:
        run_binary = cache.private_binary(binary, binary_hash, file_hash)
        if run_binary is None:
            sys.stderr.write(f"{PROG}: error: {display_path(binary)} changed while it was being copied; "
                             f"run again when the build has finished\n")
            return 2
    progress = Progress(pending, a.threads, not a.no_progress)
    progress.plan(len(jobs) - len(pending), len(recipes.renders) - len(jobs), pending)
    t0 = time.monotonic()
    sched = Scheduler(pending, run_binary, binary, cache, a.threads, a.timeout, history, progress,
                      stop_at_todo=recipes.quick)
    try:
        sched.run()
    except KeyboardInterrupt:
        sys.stderr.write(f"\n{PROG}: interrupted; finished renders are cached\n")
        cache.save_history(history)
        return 130
    wall = time.monotonic() - t0
    cache.save_history(history)

    copy_images(out_dir, recipes.renders)
    failed = [j for j in jobs if j.status == "failed"]
    flagged = [(r, render_problems(r)) for r in recipes.renders]
    flagged = [(r, p) for r, p in flagged if p]
    summary = make_summary(binary, binary_hash, recipes, jobs, pending, failed, flagged, wall, a.threads)
    write_page(out_dir, recipes, jobs, summary, binary)

    if a.prune:
        removed = cache.prune({j.key for j in jobs})
        if not a.no_progress:
            sys.stderr.write(f"{PROG}: pruned {removed} unused cache entries\n")
    report(summary, failed, flagged, out_dir, wall)
    return 1 if failed else (3 if flagged else 0)
