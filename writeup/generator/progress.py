"""Progress on stderr: one line per finished render with the elapsed time and
an ETA; on a terminal also a live status line."""

import shutil
import sys
import time

from .base import PROG, fmt_duration


class Progress:
    def __init__(self, jobs, budget, enabled):
        self.jobs = jobs
        self.total = len(jobs)
        self.budget = budget
        self.enabled = enabled
        self.tty = enabled and sys.stderr.isatty()
        self.done_n = 0
        self.t0 = time.monotonic()
        self.est_done = 0.0
        self.actual_done = 0.0
        self.last_draw = 0.0
        self.sched = None

    def eta(self, running, pending):
        """Seconds left: the estimates, scaled by how the finished renders compared to theirs."""
        ratio = self.actual_done / self.est_done if self.est_done > 0 else 1.0
        now = time.monotonic()
        remaining = sum(j.est for j in pending if not j.exclusive) / self.budget
        remaining += sum(j.est for j in pending if j.exclusive)  # run alone
        for j in running:
            left = max(0.0, j.est * ratio - (now - j.started) * j.threads)
            remaining += left / (self.budget if not j.exclusive else j.threads)
        return remaining * (ratio if pending else 1.0)

    def line(self, text):
        if not self.enabled:
            return
        if self.tty:
            sys.stderr.write("\r\033[K")
        sys.stderr.write(text + "\n")
        sys.stderr.flush()

    def done(self, job):
        self.done_n += 1
        cpu = (time.monotonic() - job.started) * job.threads
        self.est_done += job.est
        self.actual_done += cpu
        r = job.proto
        what = f"{r.grid}/{r.name}" + (f" (+{len(job.renders) - 1} same)" if len(job.renders) > 1 else "")
        status = ("FAILED: " + job.error if job.status == "failed"
                  else f"{job.meta['wall_seconds']:.1f} s, {job.threads} thread(s)")
        elapsed = time.monotonic() - self.t0
        left = self.total - self.done_n
        eta = ""
        if left and self.sched is not None:
            running = [j for j in self.sched.running if j is not job]
            eta = f", ETA {fmt_duration(self.eta(running, self.sched.pending_x + self.sched.pending))}"
        self.line(f"[{self.done_n:3d}/{self.total}] {fmt_duration(elapsed)} elapsed{eta}: {what}: {status}")

    def tick(self, running, pending):
        if not self.tty or time.monotonic() - self.last_draw < 0.5:
            return
        self.last_draw = time.monotonic()
        elapsed = time.monotonic() - self.t0
        pct = 100.0 * self.done_n / self.total if self.total else 100.0
        names = ", ".join(f"{j.proto.grid}/{j.proto.name}" for j in running)
        text = (f"{self.done_n}/{self.total} done ({pct:.0f}%), elapsed {fmt_duration(elapsed)}, "
                f"ETA {fmt_duration(self.eta(running, pending))}; rendering {names}")
        width = shutil.get_terminal_size((100, 20)).columns - 1
        sys.stderr.write("\r\033[K" + text[:width])
        sys.stderr.flush()

    def plan(self, n_cached, n_dups, pending):
        if not self.enabled:
            return
        est = (sum(j.est for j in pending if not j.exclusive) / self.budget
               + sum(j.est for j in pending if j.exclusive))
        self.line(f"{PROG}: {len(pending)} render(s) to run, {n_cached} cached"
                  + (f", {n_dups} shared by several figures" if n_dups else "")
                  + (f"; estimated {fmt_duration(est)} with {self.budget} thread(s)" if pending else ""))
