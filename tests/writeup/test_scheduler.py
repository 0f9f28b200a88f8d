#!/usr/bin/env python3
"""Unit tests of writeup/generator/scheduler.py: the order renders start in
(timing renders first and alone, then longest first), the threads each gets
within the budget, and a run with a stand-in renderer: finished renders
checked and cached, failures kept apart with their reason."""

import json
import os
import shutil
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import import_generator  # noqa: E402

import_generator()
from generator import scheduler  # noqa: E402
from generator.cache import Cache  # noqa: E402
from generator.flags import parse_flags  # noqa: E402
from generator.recipes import Render  # noqa: E402


def job(name, est=1.0, exclusive=False, threads=None, args=""):
    r = Render(where=f"recipe {name}", grid="g", name=name, label=name, scene="/nonexistent/scene.dae",
               flags=parse_flags(args, "w"), size=(8, 6), seed=1, threads=threads, exclusive=exclusive,
               quick_exclusive=False)
    j = scheduler.Job(f"{name:0>32}", r)
    j.est = est
    return j


def names(jobs):
    return [j.proto.name for j in jobs]


class OrderTest(unittest.TestCase):
    def test_run_order(self):
        jobs = [job("a", 1), job("x1", 1, exclusive=True), job("b", 5), job("c", 3), job("x2", 9, exclusive=True)]
        x, rest = scheduler.run_order(jobs)
        self.assertEqual(names(x), ["x1", "x2"])          # recipe order, not by cost
        self.assertEqual(names(rest), ["b", "c", "a"])    # longest first

    def starts(self, jobs, budget, running=()):
        """Every render next_start starts now, with its threads."""
        pending_x, pending = scheduler.run_order(jobs)
        running = list(running)
        out = []
        while True:
            nxt = scheduler.next_start(pending_x, pending, running, budget)
            if nxt is None:
                return out, pending_x, pending
            nxt[0].threads = nxt[1]
            running.append(nxt[0])
            out.append((nxt[0].proto.name, nxt[1]))

    def test_exclusive_renders_run_alone_first(self):
        jobs = [job("a"), job("x1", exclusive=True), job("x2", exclusive=True, threads=1)]
        started, pending_x, pending = self.starts(jobs, 4)
        self.assertEqual(started, [("x1", 4)])           # alone, with every thread
        self.assertEqual((names(pending_x), names(pending)), (["x2"], ["a"]))
        started, _, pending = self.starts([jobs[2], jobs[0]], 4)
        self.assertEqual(started, [("x2", 1)])           # its fixed threads, still alone
        self.assertEqual(names(pending), ["a"])
        # The last timing render too: nothing starts beside it while it runs.
        started, _, _ = self.starts([job("a")], 4, running=[jobs[2]])
        self.assertEqual(started, [])
        # Nothing starts beside a running one.
        self.assertEqual(self.starts([job("x3", exclusive=True)], 4, running=[job("r")])[0], [])

    def test_threads_are_shared_and_the_last_take_the_idle_ones(self):
        started, _, pending = self.starts([job("a", 9), job("b", 5), job("c", 1)], 4)
        # Three renders on four threads: one each, the last takes the rest.
        self.assertEqual(started, [("a", 1), ("b", 1), ("c", 2)])
        self.assertEqual(pending, [])
        started, _, _ = self.starts([job("a", 9), job("b", 5)], 8)
        self.assertEqual(started, [("a", 4), ("b", 4)])
        started, _, pending = self.starts([job(n, 10 - i) for i, n in enumerate("abcdef")], 2)
        self.assertEqual(started, [("a", 1), ("b", 1)])
        self.assertEqual(names(pending), ["c", "d", "e", "f"])

    def test_fixed_threads_wait_for_free_ones(self):
        busy = job("r")
        busy.threads = 3
        started, _, pending = self.starts([job("t", 9, threads=2), job("a", 1)], 4, running=[busy])
        self.assertEqual(started, [])                    # 1 thread free: the 2-thread render waits, in order
        self.assertEqual(names(pending), ["t", "a"])
        started, _, _ = self.starts([job("t", 9, threads=8)], 4)
        self.assertEqual(started, [("t", 4)])            # more than the budget: the budget, once alone


FAKE = """#!{python}
import json, struct, sys, time
args = sys.argv[1:]
if "-m" in args and args[args.index("-m") + 1] == "9":  # reaches a stub early, then renders on and on
    print("TODO: implement Part 2: BVH construction (bvh_build.cpp); one leaf", flush=True)
    time.sleep(120)
if "-H" in args:
    print("pathtracer: error: no such thing", file=sys.stderr)
    sys.exit(1)
if "--no-rr" not in args:
    with open(args[args.index("--stats-json") + 1], "w") as f:
        json.dump({{"render_seconds": 0.25, "max_radiance": 0 if "-o" in args else 3.5}}, f)
open(args[args.index("-f") + 1], "wb").close()
if "--pfm" in args and "-e" not in args:  # a 4 x 2 image, left half lit, for the preview
    with open(args[args.index("--pfm") + 1], "wb") as f:
        f.write(b"PF\\n4 2\\n-1\\n" + struct.pack("<24f", *([1.0] * 6 + [0.0] * 6) * 2))
print("TODO: implement Part 4 (x.cpp)" if "-o" in args else "done")
"""


class Progress:
    def __init__(self):
        self.done_jobs = []
        self.sched = None

    def done(self, j):
        self.done_jobs.append(j.proto.name)

    def tick(self, running, pending):
        pass


class RunTest(unittest.TestCase):
    def test_a_run(self):
        tmp = tempfile.mkdtemp(prefix="writeup-scheduler-")
        self.addCleanup(shutil.rmtree, tmp, True)
        binary = os.path.join(tmp, "pathtracer")
        with open(binary, "w") as f:
            f.write(FAKE.format(python=sys.executable))
        os.chmod(binary, 0o755)
        c = Cache(os.path.join(tmp, "cache"))
        os.makedirs(c.dir)
        jobs = [job("lit", 3), job("dark", 2, args="-o 0"), job("broken", 1, args="-H"), job("nojson", 0.5,
                                                                                            args="--no-rr")]
        small, nopfm = job("small", 0.4, args="-m 2"), job("nopfm", 0.3, args="-e sky.exr")
        small.proto.preview = nopfm.proto.preview = 2
        jobs += [small, nopfm]
        history, progress = {}, Progress()
        scheduler.Scheduler(jobs, binary, "/somewhere/pathtracer", c, 2, 0, history, progress).run()
        st = {j.proto.name: j for j in jobs}
        self.assertEqual(sorted(progress.done_jobs), sorted(st))
        lit, dark = st["lit"], st["dark"]
        self.assertEqual((lit.status, lit.checks["black"], lit.checks["max_radiance"]), ("ok", False, 3.5))
        self.assertEqual((dark.status, dark.checks["black"], dark.checks["todo"]),
                         ("ok", True, ["TODO: implement Part 4 (x.cpp)"]))
        # The entry keeps the checks and what they were made from.
        with open(os.path.join(c.dir, dark.key, "meta.json")) as f:
            meta = json.load(f)
        self.assertEqual(meta["checks"], dark.checks)
        self.assertEqual(meta["argv"][0], "/somewhere/pathtracer")
        self.assertEqual(meta["argv"][-8:], ["-t", str(dark.threads), "--no-progress", "--stats-json",
                                             "render.json", "-f", "render.png", "/nonexistent/scene.dae"])
        for f in ("render.json", "render.png", "log.txt"):
            self.assertTrue(os.path.isfile(os.path.join(c.dir, dark.key, f)), f)
        self.assertEqual(len(history), 3)                 # the times of the renders that succeeded
        broken, nojson = st["broken"], st["nojson"]
        self.assertEqual(broken.status, "failed")
        self.assertEqual(broken.error, "pathtracer exited with status 1: pathtracer: error: no such thing")
        self.assertEqual(broken.dir, os.path.join(c.dir, "failed", broken.key))
        self.assertEqual((nojson.status, nojson.error), ("failed", "pathtracer exited with status 0 but wrote "
                                                                   "no render.json"))
        self.assertFalse(os.path.exists(os.path.join(c.dir, broken.key)))
        # --quick: the PNG is the PFM shrunk, the PFM deleted, and what the
        # preview shows kept with the checks; without a PFM the render failed.
        self.assertEqual((small.status, small.checks["preview"]),
                         ("ok", {"width": 2, "height": 1, "flat": False, "color": [255, 255, 255]}))
        self.assertIn("--pfm", small.argv)
        self.assertEqual(sorted(os.listdir(os.path.join(c.dir, small.key))),
                         ["log.txt", "meta.json", "render.json", "render.png"])
        self.assertEqual(nopfm.status, "failed")
        self.assertIn("cannot make the preview from the render's --pfm output", nopfm.error)
        self.assertNotIn("preview", lit.checks)
        self.assertEqual(sorted(os.listdir(c.dir)), sorted(["failed", lit.key, dark.key, small.key]))


class StopAtTodoTest(unittest.TestCase):
    def test_quick_stops_a_render_at_its_first_todo_line(self):
        """--quick (stop_at_todo): a render that prints a TODO line is not
        made, whether it is still running (stopped at once, not after its
        two minutes) or has ended; the others are made as usual."""
        tmp = tempfile.mkdtemp(prefix="writeup-scheduler-")
        self.addCleanup(shutil.rmtree, tmp, True)
        binary = os.path.join(tmp, "pathtracer")
        with open(binary, "w") as f:
            f.write(FAKE.format(python=sys.executable))
        os.chmod(binary, 0o755)
        c = Cache(os.path.join(tmp, "cache"))
        os.makedirs(c.dir)
        jobs = [job("slow", 3, args="-m 9"), job("dark", 2, args="-o 0"), job("lit", 1)]
        scheduler.Scheduler(jobs, binary, binary, c, 2, 0, {}, Progress(), stop_at_todo=True).run()
        st = {j.proto.name: j for j in jobs}
        for name, line in (("slow", "TODO: implement Part 2: BVH construction (bvh_build.cpp); one leaf"),
                           ("dark", "TODO: implement Part 4 (x.cpp)")):
            self.assertEqual(st[name].status, "failed", name)
            self.assertEqual(st[name].error, f"stopped at its first TODO line, '{line}': --quick does not finish a "
                                             f"render that reaches code not written yet")
        self.assertEqual((st["lit"].status, st["lit"].checks["todo"]), ("ok", []))


if __name__ == "__main__":
    unittest.main()
