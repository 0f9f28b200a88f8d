"""Running the renders: several at once within the thread budget (-t), timing
renders first and alone, the rest longest first; each finished render is
checked and stored in the cache."""

import datetime
import json
import os
import shutil
import signal
import subprocess
import time

from . import checks, preview
from .base import display_path
from .cache import command_key, entry_images
from .flags import get_flag, recipe_args


class Job:
    """One distinct render, shared by every figure whose render has the same cache key."""

    def __init__(self, key, render):
        self.key = key
        self.renders = [render]
        self.proto = render
        self.threads_fixed = render.threads
        self.exclusive = render.exclusive
        self.status = None      # "cached", "ok", "failed"
        self.error = None
        self.meta = None
        self.stats = None
        self.est = 0.0
        self.proc = None
        self.log = None
        self.started = 0.0
        self.threads = 1
        self.tmp = None
        self.dir = None
        self.cpu = None
        self.checks = None      # checks.make_checks() of a finished render
        self.preview = None     # --quick: what preview.make_preview() found
        self.log_seen = 0       # bytes of log.txt already looked at for a TODO line


def make_jobs(renders, key_of):
    """One job per distinct key_of(render); a render several figures share runs once."""
    jobs = {}
    for r in renders:
        key = key_of(r)
        if key in jobs:
            jobs[key].renders.append(r)
            jobs[key].exclusive = jobs[key].exclusive or r.exclusive
        else:
            jobs[key] = Job(key, r)
        r.job = jobs[key]
    return list(jobs.values())


def cost_units(r):
    """A rough guess at a render's CPU cost, for the ETA before any history exists."""
    w, h = r.size
    spp = int(get_flag(r.flags, "-s", ["1"])[0])
    l = int(get_flag(r.flags, "-l", ["1"])[0])
    m = int(get_flag(r.flags, "-m", ["1"])[0])
    part = int(get_flag(r.flags, "--part", ["9"])[0])
    prims = os.path.getsize(r.scene) / 32.0
    if part == 1:
        per_ray = 1 + prims / 15.0
    elif part == 2:
        per_ray = 1.0
    else:
        per_ray = 1 + 2 * l
        if part >= 4:
            depth = min(m, 12) if get_flag(r.flags, "--no-rr") is not None else min(m, 5)
            per_ray *= 1 + 0.6 * depth
        if part >= 5 and spp > 1:
            spp = max(1, spp // 4)
    load = prims / 2e5 * 1.5  # seconds to load and build
    return w * h * spp * per_ray * 4e-7 + load + 0.05


def run_order(jobs):
    """The order renders start in: the exclusive (timing) ones first, in recipe
    order; then the rest, longest (by estimate) first."""
    return ([j for j in jobs if j.exclusive],
            sorted((j for j in jobs if not j.exclusive), key=lambda j: -j.est))


def next_start(pending_x, pending, running, budget):
    """The render to start now and its thread count, taken out of its list, or
    None. Exclusive renders run alone, one at a time, before the others; a
    render with fixed threads waits until they are free (or nothing runs); the
    others share the free threads, so the last ones take those that would
    otherwise sit idle."""
    free = budget - sum(j.threads for j in running)
    if any(j.exclusive for j in running):
        return None  # a timing render runs alone, also when it leaves threads free
    if pending_x:
        if running:
            return None
        job = pending_x.pop(0)
        return job, (min(job.threads_fixed, budget) if job.threads_fixed else budget)
    if not pending or free <= 0:
        return None
    job = pending[0]
    if job.threads_fixed:
        if job.threads_fixed > free and running:
            return None
        threads = min(job.threads_fixed, budget)
    else:
        threads = max(1, free // len(pending))
    pending.pop(0)
    return job, threads


def kill(proc):
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def last_line(path):
    """The log's last line that says "error", else its last line."""
    try:
        with open(path, "rb") as f:
            lines = [l.strip() for l in f.read().decode("utf-8", "replace").splitlines() if l.strip()]
    except OSError:
        return ""
    for l in reversed(lines):
        if "error" in l.lower():
            return l
    return lines[-1] if lines else ""


class Scheduler:
    def __init__(self, jobs, binary, display_binary, cache, budget, timeout, history, progress, stop_at_todo=False):
        self.jobs = jobs
        # --quick: a render that reaches code not written yet (its first TODO
        # line) is stopped at once: its image could not show the figure, and
        # through stand-ins (a one-leaf BVH) it would be slow.
        self.stop_at_todo = stop_at_todo
        self.binary = binary                  # the private copy renders run with
        self.display_binary = display_binary  # the binary as given, for the commands shown
        self.cache = cache
        self.budget = budget
        self.timeout = timeout
        self.history = history
        self.progress = progress
        self.pending_x, self.pending = run_order(jobs)
        self.running = []

    def start(self, job, threads):
        r = job.proto
        job.threads = threads
        job.tmp = self.cache.new_entry(job.key)
        extra = ["--env-probability", "render_env_probability.png"] if r.env_probability else []
        if r.preview > 1:
            extra += ["--pfm", "render.pfm"]  # the preview is made from it (preview.py)
        job.argv = ([self.binary] + recipe_args(r) + ["-t", str(threads), "--no-progress",
                                                      "--stats-json", "render.json"] + extra
                    + ["-f", "render.png", r.scene])
        job.log = open(os.path.join(job.tmp, "log.txt"), "wb")
        job.started = time.monotonic()
        try:
            job.proc = subprocess.Popen(job.argv, cwd=job.tmp, stdout=job.log, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, start_new_session=True)
        except OSError as e:
            job.log.close()
            job.proc = None
            self.finish(job, None, f"cannot run {display_path(self.binary)}: {e.strerror}")

    def poll(self, job):
        """The exit status once the render has ended (None before), noting its CPU time."""
        try:
            pid, status, usage = os.wait4(job.proc.pid, os.WNOHANG)
        except ChildProcessError:
            return job.proc.poll()
        if pid == 0:
            return None
        job.cpu = usage.ru_utime + usage.ru_stime
        job.proc.returncode = os.waitstatus_to_exitcode(status)
        return job.proc.returncode

    def outcome(self, job, rc):
        """None when the render succeeded (its stats read), else what went wrong."""
        if rc != 0:
            error = f"pathtracer {'was killed by signal ' + str(-rc) if rc < 0 else 'exited with status ' + str(rc)}"
            last = last_line(os.path.join(job.tmp, "log.txt"))
            return error + (f": {last}" if last else "")
        for f in entry_images(job.proto) + ["render.json"]:
            if not os.path.isfile(os.path.join(job.tmp, f)):
                return f"pathtracer exited with status 0 but wrote no {f}"
        try:
            with open(os.path.join(job.tmp, "render.json")) as f:
                job.stats = json.load(f)
        except (OSError, ValueError) as e:
            return f"unreadable --stats-json output: {e}"
        return None

    def finish(self, job, rc, error=None):
        wall = time.monotonic() - job.started
        if job.log and not job.log.closed:
            job.log.close()
        if error is None:
            error = self.outcome(job, rc)
        if error is None and job.proto.preview > 1:
            error = self.make_preview(job)
        if error is None:
            job.checks = checks.make_checks(os.path.join(job.tmp, "log.txt"), job.stats)
            if job.preview is not None:
                job.checks["preview"] = job.preview
        job.meta = {"argv": [display_path(self.display_binary)] + job.argv[1:-1] + [display_path(job.argv[-1])],
                    "threads": job.threads, "wall_seconds": round(wall, 3),
                    "cpu_seconds": round(job.cpu, 3) if job.cpu is not None else None,
                    "date": datetime.datetime.now().isoformat(timespec="seconds"),
                    "recipe": job.proto.where}
        if job.checks is not None:
            job.meta["checks"] = job.checks  # kept with the cache entry: a cache hit is flagged alike
        if error is not None:
            job.status, job.error = "failed", error
            job.dir = self.cache.store_failed(job, job.tmp)
        else:
            job.dir = self.cache.store(job, job.tmp)
            job.status = "ok"
            self.history[command_key(job.proto)] = wall * job.threads
        self.progress.done(job)

    def make_preview(self, job):
        """--quick: the render's PNG replaced by its preview (preview.py),
        and its PFM deleted; None, or what went wrong."""
        pfm = os.path.join(job.tmp, "render.pfm")
        try:
            job.preview = preview.make_preview(pfm, os.path.join(job.tmp, "render.png"), job.proto.preview)
        except (OSError, ValueError) as e:
            return f"cannot make the preview from the render's --pfm output: {e}"
        finally:
            if os.path.exists(pfm):
                os.remove(pfm)
        return None

    def first_todo_line(self, job, ended):
        """The first TODO line the render has printed, or None (its log read on
        from where the last look stopped; once it has ended, to the end)."""
        try:
            with open(os.path.join(job.tmp, "log.txt"), "rb") as f:
                f.seek(job.log_seen)
                text = f.read()
        except OSError:
            return None
        # Only whole lines while it runs: a line being written is read next time.
        end = len(text) if ended else text.rfind(b"\n") + 1
        job.log_seen += end
        for line in text[:end].decode("utf-8", "replace").splitlines():
            m = checks.TODO_LINE.search(line)
            if m:
                return line[m.start():].strip()
        return None

    def reap(self):
        """Finishes the renders that have ended or run out of time (and, with
        stop_at_todo, those that printed a TODO line)."""
        for job in list(self.running):
            rc = self.poll(job)
            # Whether it is stopped or has just ended, a render that printed a
            # TODO line comes out the same way: not made.
            todo = self.first_todo_line(job, rc is not None) if self.stop_at_todo else None
            if todo is not None:
                if rc is None:
                    kill(job.proc)
                    job.proc.wait()
                self.running.remove(job)
                self.finish(job, None, f"stopped at its first TODO line, '{todo}': --quick does not finish a render "
                                       f"that reaches code not written yet")
            elif rc is None and self.timeout and time.monotonic() - job.started > self.timeout:
                kill(job.proc)
                job.proc.wait()
                self.running.remove(job)
                self.finish(job, None, f"timed out after {self.timeout:g} s (--timeout)")
            elif rc is not None:
                self.running.remove(job)
                self.finish(job, rc)

    def run(self):
        self.progress.sched = self
        try:
            while self.pending_x or self.pending or self.running:
                self.reap()
                while True:
                    nxt = next_start(self.pending_x, self.pending, self.running, self.budget)
                    if nxt is None:
                        break
                    self.start(*nxt)
                    if nxt[0].proc:
                        self.running.append(nxt[0])
                    elif nxt[0].exclusive:
                        break  # the next timing render starts on the next round
                self.progress.tick(self.running, self.pending_x + self.pending)
                time.sleep(0.05)
        except KeyboardInterrupt:
            for job in self.running:
                kill(job.proc)
                job.proc.wait()
                shutil.rmtree(job.tmp, ignore_errors=True)
            raise
