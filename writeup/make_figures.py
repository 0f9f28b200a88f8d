#!/usr/bin/env python3
"""Render the write-up's figures and lay them out as a page.

    python3 writeup/make_figures.py [--quick] [--pathtracer PATH] [-t N] [--out DIR]

Reads the figure recipes (writeup/figures.toml), renders every figure with a
pathtracer binary (default build/bin/pathtracer), several renders at once
within the -t thread budget, and writes OUT/index.html and OUT/index.md
(default OUT: writeup/out). Each render is cached under OUT/cache by a hash
of its command line, of the binary's bytes and of the scene file's bytes,
so a second run renders only what changed. See writeup/README.md.

Exit status: 0 when every render succeeded and no figure is flagged; 1
when some render failed (the page is still written and shows them); 2 for
bad input (recipes, binary, options); 3 when every render ran but some
figure is flagged: the renderer printed a "TODO:" line for it (a function
not written yet) or its image is all black (the page shows which and why).
A failed render takes precedence: 1 even if some figure is flagged too.
"""

import argparse
import datetime
import fnmatch
import hashlib
import html
import json
import os
import re
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import time
import zlib

try:
    import tomllib
except ImportError:  # Python < 3.11
    sys.stderr.write("make_figures.py: error: Python 3.11 or newer is needed (tomllib)\n")
    sys.exit(2)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROG = "make_figures.py"

# The pathtracer's flags and how many values each takes (pathtracer --help).
FLAG_ARITY = {
    "-s": 1, "-l": 1, "-t": 1, "-m": 1, "-o": 1, "-e": 1, "-b": 1, "-d": 1,
    "-f": 1, "-r": 2, "-c": 1, "-a": 2, "-H": 0, "-p": 4, "--part": 1,
    "--seed": 1, "--pfm": 1, "--stats-json": 1, "--bvh-leaf": 1,
    "--bvh-bins": 1, "--no-rr": 0, "--direct-only": 0, "--indirect-only": 0,
    "--course-area-pdf": 0, "--no-progress": 0,
}
# Set by the generator itself (from size, seed, the scheduler and the cache).
GENERATED_FLAGS = {"-r": "size", "--seed": "seed", "-t": "threads",
                   "-f": None, "--stats-json": None, "--no-progress": None,
                   "--pfm": None}
FILE_FLAGS = ("-e", "-c")  # their files' bytes are part of the cache key

SETTINGS_KEYS = {"title", "scenes_dir", "size", "seed", "quick_size",
                 "quick_max_samples", "quick_max_light_samples"}
SECTION_KEYS = {"id", "title", "text", "grid", "table"}
GRID_KEYS = {"id", "title", "text", "scene", "args", "size", "quick_size", "seed",
             "columns", "rate", "vary", "cells", "expect_black"}
CELL_KEYS = {"label", "name", "scene", "args", "size", "quick_size", "seed", "expect_black"}
VARY_KEYS = {"flag", "values"}
TABLE_KEYS = {"id", "title", "text", "scene", "scenes", "args", "size", "quick_size",
              "seed", "threads", "exclusive", "variants", "columns"}
VARIANT_KEYS = {"label", "args"}
COLUMN_KEYS = {"title", "field", "variant", "ratio"}


class InputError(Exception):
    """Bad input: reported as one line, exit status 2."""


# ---------------------------------------------------------------------------
# Recipes

def check_keys(table, known, where):
    if not isinstance(table, dict):
        raise InputError(f"{where}: expected a table, got {type(table).__name__}")
    for k in table:
        if k not in known:
            raise InputError(f"{where}: unknown field '{k}' (known fields: {', '.join(sorted(known))})")


def want(value, types, where, what):
    """value if it has one of the types (a bool is not taken for an int)."""
    types = types if isinstance(types, tuple) else (types,)
    if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
        names = " or ".join({str: "a string", int: "an integer", bool: "true or false",
                             list: "a list", dict: "a table"}.get(t, t.__name__) for t in types)
        raise InputError(f"{where}: '{what}' must be {names}, got {value!r}")
    return value


def want_size(value, where, what="size"):
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value)):
        raise InputError(f"{where}: '{what}' must be [width, height] with positive integers, got {value!r}")
    return (value[0], value[1])


def parse_flags(text, where):
    """pathtracer arguments as a list of (flag, [values])."""
    if not isinstance(text, str):
        raise InputError(f"{where}: 'args' must be a string of pathtracer flags")
    try:
        tokens = shlex.split(text)
    except ValueError as e:
        raise InputError(f"{where}: cannot split args '{text}': {e}")
    flags = []
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok not in FLAG_ARITY:
            raise InputError(f"{where}: unknown pathtracer flag '{tok}' in args '{text}'")
        if tok in GENERATED_FLAGS:
            field = GENERATED_FLAGS[tok]
            hint = f" (use the recipe's '{field}' field)" if field else ""
            raise InputError(f"{where}: the generator sets {tok} itself{hint}")
        n = FLAG_ARITY[tok]
        vals = tokens[i + 1:i + 1 + n]
        if len(vals) != n or any(v in FLAG_ARITY for v in vals):
            raise InputError(f"{where}: {tok} needs {n} value(s) in args '{text}'")
        flags.append((tok, list(vals)))
        i += 1 + n
    return flags


def merge_flags(base, extra):
    """base's flags with extra's: a flag in both takes extra's values in base's place."""
    out = [(f, list(v)) for f, v in base]
    for flag, vals in extra:
        for i, (f, _) in enumerate(out):
            if f == flag:
                out[i] = (flag, list(vals))
                break
        else:
            out.append((flag, list(vals)))
    return out


def get_flag(flags, flag, default=None):
    for f, v in flags:
        if f == flag:
            return v
    return default


def set_flag(flags, flag, vals):
    return merge_flags(flags, [(flag, vals)])


def slug(text):
    s = re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_").lower()
    return s or "render"


class Render:
    """One image of the page (a grid cell or a table entry)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)
        self.job = None
        self.rate = False
        self.expect_black = False


class Recipes:
    def __init__(self, path, quick):
        self.path = path
        self.display = display_path(path)
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except FileNotFoundError:
            raise InputError(f"{self.display}: recipe file not found")
        except tomllib.TOMLDecodeError as e:
            raise InputError(f"{self.display}: not valid TOML: {e}")
        self.quick = quick
        check_keys(data, {"settings", "section"}, self.display)
        s = data.get("settings", {})
        where = f"{self.display}: [settings]"
        check_keys(s, SETTINGS_KEYS, where)
        self.title = want(s.get("title", "PathTracer write-up figures"), str, where, "title")
        scenes_dir = want(s.get("scenes_dir", "../scenes"), str, where, "scenes_dir")
        self.scenes_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), scenes_dir))
        self.size = want_size(s.get("size", [480, 360]), where)
        self.seed = want(s.get("seed", 1), int, where, "seed")
        self.quick_size = want_size(s.get("quick_size", [64, 48]), where, "quick_size")
        self.quick_max_samples = want(s.get("quick_max_samples", 8), int, where, "quick_max_samples")
        self.quick_max_light_samples = want(s.get("quick_max_light_samples", 4), int, where, "quick_max_light_samples")
        self.sections = []
        self.renders = []
        ids = set()
        sections = data.get("section", [])
        if not isinstance(sections, list) or not sections:
            raise InputError(f"{self.display}: no [[section]]")
        for n, sec in enumerate(sections, 1):
            where = f"{self.display}: section {n}"
            check_keys(sec, SECTION_KEYS, where)
            sid = want(sec.get("id", f"section{n}"), str, where, "id")
            where = f"{self.display}: section '{sid}'"
            section = {"id": sid, "title": want(sec.get("title", sid), str, where, "title"),
                       "text": want(sec.get("text", ""), str, where, "text"), "items": []}
            for g in want(sec.get("grid", []), list, where, "grid"):
                section["items"].append(self._grid(g, ids, where))
            for t in want(sec.get("table", []), list, where, "table"):
                section["items"].append(self._table(t, ids, where))
            self.sections.append(section)

    def _id(self, item, ids, where, kind):
        if "id" not in item:
            raise InputError(f"{where}: a {kind} has no 'id'")
        gid = want(item["id"], str, where, "id")
        if not re.fullmatch(r"[A-Za-z0-9_-]+", gid):
            raise InputError(f"{where}: {kind} id '{gid}' may only hold letters, digits, '_' and '-'")
        if gid in ids:
            raise InputError(f"{where}: {kind} id '{gid}' is used twice")
        ids.add(gid)
        return gid

    def _scene(self, name, where):
        if not isinstance(name, str) or not name:
            raise InputError(f"{where}: no 'scene'")
        path = name if os.path.isabs(name) else os.path.join(self.scenes_dir, name)
        if not os.path.isfile(path):
            raise InputError(f"{where}: scene file not found: {display_path(path)}")
        return os.path.abspath(path)

    def _render(self, where, gid, name, label, scene, flags, size, quick_size, seed, threads=None, exclusive=False):
        scene_path = self._scene(scene, where)
        quick_exclusive = False
        if self.quick:
            # Quick renders are checks, not timings: no render needs to run alone.
            quick_exclusive, exclusive = exclusive, False
            size = (min(size[0], quick_size[0]), min(size[1], quick_size[1]))
            s = get_flag(flags, "-s")
            if s is not None and int(s[0]) > self.quick_max_samples:
                flags = set_flag(flags, "-s", [str(self.quick_max_samples)])
            l = get_flag(flags, "-l")
            if l is not None and int(l[0]) > self.quick_max_light_samples:
                flags = set_flag(flags, "-l", [str(self.quick_max_light_samples)])
            a = get_flag(flags, "-a")
            if a is not None:
                smax = int(get_flag(flags, "-s", ["1"])[0])
                if int(a[0]) > smax:
                    flags = set_flag(flags, "-a", [str(smax), a[1]])
        for flag in FILE_FLAGS:
            v = get_flag(flags, flag)
            if v is not None:
                p = v[0] if os.path.isabs(v[0]) else os.path.join(ROOT, v[0])
                if not os.path.isfile(p):
                    raise InputError(f"{where}: {flag} file not found: {v[0]}")
                flags = set_flag(flags, flag, [os.path.abspath(p)])
        r = Render(where=where, grid=gid, name=name, label=label, scene=scene_path,
                   flags=flags, size=size, seed=seed, threads=threads, exclusive=exclusive,
                   quick_exclusive=quick_exclusive)
        self.renders.append(r)
        return r

    def _shared_fields(self, x, where):
        """The fields grids and tables share: args, size, quick_size, seed."""
        base = parse_flags(x.get("args", ""), where)
        size = want_size(x["size"], where) if "size" in x else self.size
        qsize = want_size(x["quick_size"], where, "quick_size") if "quick_size" in x else self.quick_size
        seed = want(x.get("seed", self.seed), int, where, "seed")
        return base, size, qsize, seed

    def _expect_black(self, value, where):
        """A recipe's expect_black (true, false or "quick") as a yes or no for this run."""
        if value not in (True, False, "quick"):
            raise InputError(f"{where}: 'expect_black' must be true, false or \"quick\", got {value!r}")
        return value is True or (value == "quick" and self.quick)

    def _grid(self, g, ids, where):
        gid = self._id(g, ids, where, "grid")
        where = f"{self.display}: grid '{gid}'"
        check_keys(g, GRID_KEYS, where)
        base, size, qsize, seed = self._shared_fields(g, where)
        columns = want(g.get("columns", 0), int, where, "columns")
        rate = want(g.get("rate", False), bool, where, "rate")
        black = g.get("expect_black", False)
        self._expect_black(black, where)
        grid = {"kind": "grid", "id": gid, "title": want(g.get("title", gid), str, where, "title"),
                "text": want(g.get("text", ""), str, where, "text"),
                "rate": rate, "renders": []}
        if ("vary" in g) == ("cells" in g):
            raise InputError(f"{where}: give either 'vary' or 'cells'")
        names = set()
        if "vary" in g:
            v = g["vary"]
            check_keys(v, VARY_KEYS, f"{where}: vary")
            flag = want(v.get("flag"), str, f"{where}: vary", "flag")
            values = want(v.get("values"), list, f"{where}: vary", "values")
            if not values:
                raise InputError(f"{where}: vary has no values")
            cells = []
            for val in values:
                vals = [str(x) for x in val] if isinstance(val, list) else [str(val)]
                cells.append({"label": f"{flag} {' '.join(vals)}", "name": slug(flag + "_" + "_".join(vals)),
                              "args": shlex.join([flag] + vals)})
        else:
            cells = want(g["cells"], list, where, "cells")
            if not cells:
                raise InputError(f"{where}: 'cells' is empty")
        for n, c in enumerate(cells, 1):
            cw = f"{where}, cell {n}"
            check_keys(c, CELL_KEYS, cw)
            label = want(c.get("label", f"{n}"), str, cw, "label")
            cw = f"{where}, cell '{label}'"
            # Default file name: the label without ".dae" and without parentheses.
            default = re.sub(r"\([^)]*\)|\.dae\b", "", label) if "name" not in c else c["name"]
            name = slug(want(default, str, cw, "name"))
            base_name, k = name, 2
            while name in names:
                name, k = f"{base_name}_{k}", k + 1
            names.add(name)
            flags = merge_flags(base, parse_flags(c.get("args", ""), cw))
            csize = want_size(c["size"], cw) if "size" in c else size
            cqsize = want_size(c["quick_size"], cw, "quick_size") if "quick_size" in c else qsize
            cseed = want(c.get("seed", seed), int, cw, "seed")
            r = self._render(cw, gid, name, label, c.get("scene", g.get("scene")), flags, csize, cqsize, cseed)
            r.rate = rate
            r.expect_black = self._expect_black(c.get("expect_black", black), cw)
            grid["renders"].append(r)
        grid["columns"] = columns if columns > 0 else min(len(grid["renders"]), 4 if not grid["rate"] else 2)
        return grid

    def _table(self, t, ids, where):
        tid = self._id(t, ids, where, "table")
        where = f"{self.display}: table '{tid}'"
        check_keys(t, TABLE_KEYS, where)
        base, size, qsize, seed = self._shared_fields(t, where)
        threads = t.get("threads")
        if threads is not None and (not isinstance(threads, int) or threads < 1):
            raise InputError(f"{where}: 'threads' must be a positive integer")
        exclusive = want(t.get("exclusive", False), bool, where, "exclusive")
        scenes = want(t.get("scenes", [t["scene"]] if "scene" in t else []), list, where, "scenes")
        if not scenes:
            raise InputError(f"{where}: no 'scenes'")
        variants = want(t.get("variants", [{"label": "render"}]), list, where, "variants")
        vlabels = []
        for n, v in enumerate(variants, 1):
            check_keys(v, VARIANT_KEYS, f"{where}, variant {n}")
            vlabels.append(want(v.get("label", f"variant {n}"), str, f"{where}, variant {n}", "label"))
        columns = want(t.get("columns", []), list, where, "columns")
        if not columns:
            raise InputError(f"{where}: no 'columns'")
        for n, c in enumerate(columns, 1):
            cw = f"{where}, column {n}"
            check_keys(c, COLUMN_KEYS, cw)
            if ("field" in c) == ("ratio" in c):
                raise InputError(f"{cw}: give either 'field' (with 'variant') or 'ratio'")
            if "field" in c:
                want(c["field"], str, cw, "field")
                if c.get("variant", vlabels[0]) not in vlabels:
                    raise InputError(f"{cw}: unknown variant '{c.get('variant')}' (variants: {', '.join(vlabels)})")
            else:
                r = c["ratio"]
                if not (isinstance(r, list) and len(r) == 3 and all(isinstance(x, str) for x in r)
                        and r[1] in vlabels and r[2] in vlabels):
                    raise InputError(f"{cw}: 'ratio' must be [field, variant, variant] with variants among {', '.join(vlabels)}")
        table = {"kind": "table", "id": tid, "title": want(t.get("title", tid), str, where, "title"),
                 "text": want(t.get("text", ""), str, where, "text"), "columns": columns,
                 "variants": vlabels, "rows": []}
        for scene in scenes:
            want(scene, str, where, "scenes")
            row = {"scene": scene, "renders": {}}
            for v, vl in zip(variants, vlabels):
                vw = f"{where}, scene '{scene}', variant '{vl}'"
                flags = merge_flags(base, parse_flags(v.get("args", ""), vw))
                row["renders"][vl] = self._render(vw, tid, slug(f"{os.path.splitext(scene)[0]}_{vl}"),
                                                  f"{scene}, {vl}", scene, flags, size, qsize, seed,
                                                  threads=threads, exclusive=exclusive)
            table["rows"].append(row)
        return table


# ---------------------------------------------------------------------------
# Commands, cache keys, cost estimates

def display_path(path):
    """A path as shown to people: relative to the repository root when inside it."""
    a = os.path.abspath(path)
    rel = os.path.relpath(a, ROOT)
    return a if rel.startswith("..") else rel


_file_hashes = {}


def file_hash(path):
    st = os.stat(path)
    key = (path, st.st_size, st.st_mtime_ns)
    if key not in _file_hashes:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _file_hashes[key] = h.hexdigest()
    return _file_hashes[key]


def flat(flags):
    out = []
    for f, v in flags:
        out.append(f)
        out.extend(v)
    return out


def recipe_args(r):
    """The render's arguments that decide the image (no threads, no output paths)."""
    return flat(r.flags) + ["-r", str(r.size[0]), str(r.size[1]), "--seed", str(r.seed)]


def command_key(r):
    """Identifies the recipe without the binary: for the timing history."""
    parts = recipe_args(r) + [display_path(r.scene)]
    if r.threads is not None:
        parts += ["-t", str(r.threads)]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:24]


def cache_key(r, binary_hash):
    """The command line (without -t unless the recipe fixes it, and without output
    paths), the binary's bytes, and the bytes of the files the command reads."""
    files = [file_hash(r.scene)] + [file_hash(get_flag(r.flags, f)[0]) for f in FILE_FLAGS if get_flag(r.flags, f)]
    desc = json.dumps({"args": recipe_args(r), "threads": r.threads, "binary": binary_hash,
                       "scene": os.path.basename(r.scene), "files": files})
    return hashlib.sha256(desc.encode()).hexdigest()[:32]


def cost_units(r):
    """A rough guess at a render's CPU cost, for the ETA before any history exists."""
    w, h = r.size
    spp = int(get_flag(r.flags, "-s", ["1"])[0])
    l = int(get_flag(r.flags, "-l", ["1"])[0])
    m = int(get_flag(r.flags, "-m", ["1"])[0])
    part = int(get_flag(r.flags, "--part", ["5"])[0])
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
        if part == 5 and spp > 1:
            spp = max(1, spp // 4)
    load = prims / 2e5 * 1.5  # seconds to load and build
    return w * h * spp * per_ray * 4e-7 + load + 0.05


# ---------------------------------------------------------------------------
# Running renders

class Job:
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
        self.started = 0.0
        self.threads = 1
        self.tmp = None
        self.cpu = None
        self.checks = None      # render_checks() of a finished render


class Scheduler:
    def __init__(self, jobs, binary, cache_dir, budget, timeout, history, progress):
        self.jobs = jobs
        self.binary = binary
        self.cache_dir = cache_dir
        self.budget = budget
        self.timeout = timeout
        self.history = history
        self.progress = progress

    def start(self, job, threads):
        r = job.proto
        job.threads = threads
        job.tmp = os.path.join(self.cache_dir, f"{job.key}.tmp-{os.getpid()}")
        shutil.rmtree(job.tmp, ignore_errors=True)
        os.makedirs(job.tmp)
        argv = ([self.binary] + recipe_args(r) + ["-t", str(threads), "--no-progress",
                                                  "--stats-json", "render.json", "-f", "render.png", r.scene])
        job.argv = argv
        job.log = open(os.path.join(job.tmp, "log.txt"), "wb")
        job.started = time.monotonic()
        try:
            job.proc = subprocess.Popen(argv, cwd=job.tmp, stdout=job.log, stderr=subprocess.STDOUT,
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

    def finish(self, job, rc, error=None):
        wall = time.monotonic() - job.started
        if job.log and not job.log.closed:
            job.log.close()
        log_path = os.path.join(job.tmp, "log.txt")
        if error is None and rc != 0:
            error = f"pathtracer {'was killed by signal ' + str(-rc) if rc < 0 else 'exited with status ' + str(rc)}"
            last = last_line(log_path)
            if last:
                error += f": {last}"
        if error is None:
            for f in ("render.png", "render.json"):
                if not os.path.isfile(os.path.join(job.tmp, f)):
                    error = f"pathtracer exited with status 0 but wrote no {f}"
                    break
        if error is None:
            try:
                with open(os.path.join(job.tmp, "render.json")) as f:
                    job.stats = json.load(f)
            except (OSError, ValueError) as e:
                error = f"unreadable --stats-json output: {e}"
        if error is None:
            job.checks = render_checks(job.tmp)
        job.meta = {"argv": [display_path(self.display_binary)] + job.argv[1:-1] + [display_path(job.argv[-1])],
                    "threads": job.threads, "wall_seconds": round(wall, 3),
                    "cpu_seconds": round(job.cpu, 3) if job.cpu is not None else None,
                    "date": datetime.datetime.now().isoformat(timespec="seconds"),
                    "recipe": job.proto.where}
        if job.checks is not None:
            job.meta["checks"] = job.checks  # kept with the cache entry: a cache hit is flagged alike
        if error is not None:
            job.status, job.error = "failed", error
            failed_dir = os.path.join(self.cache_dir, "failed", job.key)
            shutil.rmtree(failed_dir, ignore_errors=True)
            os.makedirs(os.path.dirname(failed_dir), exist_ok=True)
            os.replace(job.tmp, failed_dir)
            job.dir = failed_dir
        else:
            with open(os.path.join(job.tmp, "meta.json"), "w") as f:
                json.dump(job.meta, f, indent=1)
            final = os.path.join(self.cache_dir, job.key)
            shutil.rmtree(final, ignore_errors=True)
            os.replace(job.tmp, final)
            job.dir = final
            job.status = "ok"
            self.history[command_key(job.proto)] = wall * job.threads
        self.progress.done(job)

    def run(self):
        # Timing renders first, alone; then the rest, longest first.
        pending_x = self.pending_x = [j for j in self.jobs if j.exclusive]
        pending = self.pending = sorted((j for j in self.jobs if not j.exclusive), key=lambda j: -j.est)
        running = self.running = []
        self.progress.sched = self
        try:
            while pending_x or pending or running:
                for job in list(running):
                    rc = self.poll(job)
                    if rc is None and self.timeout and time.monotonic() - job.started > self.timeout:
                        kill(job.proc)
                        job.proc.wait()
                        running.remove(job)
                        self.finish(job, None, f"timed out after {self.timeout:g} s (--timeout)")
                    elif rc is not None:
                        running.remove(job)
                        self.finish(job, rc)
                free = self.budget - sum(j.threads for j in running)
                if pending_x:
                    # Timing renders run alone, one at a time.
                    if not running:
                        job = pending_x.pop(0)
                        self.start(job, min(job.threads_fixed or 1, self.budget) if job.threads_fixed else self.budget)
                        if job.proc:
                            running.append(job)
                else:
                    while pending and free > 0:
                        job = pending.pop(0)
                        if job.threads_fixed:
                            if job.threads_fixed > free and running:
                                pending.insert(0, job)
                                break
                            threads = min(job.threads_fixed, self.budget)
                        else:
                            # The last renders share the threads that would sit idle.
                            threads = max(1, free // (len(pending) + 1))
                        self.start(job, threads)
                        if job.proc:
                            running.append(job)
                            free -= threads
                self.progress.tick(running, pending_x + pending)
                time.sleep(0.05)
        except KeyboardInterrupt:
            for job in running:
                kill(job.proc)
                job.proc.wait()
                shutil.rmtree(job.tmp, ignore_errors=True)
            raise


def kill(proc):
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def last_line(path):
    try:
        with open(path, "rb") as f:
            lines = [l.strip() for l in f.read().decode("utf-8", "replace").splitlines() if l.strip()]
    except OSError:
        return ""
    for l in reversed(lines):
        if "error" in l.lower():
            return l
    return lines[-1] if lines else ""


# ---------------------------------------------------------------------------
# Checking a finished render: TODO lines in its log, an all-black image

TODO_LINE = re.compile(r"(?<![A-Za-z0-9_])TODO:")


def todo_lines(log_path):
    """The distinct 'TODO: ...' lines of a render's log, in order. A starter-kit
    build prints one the first time it reaches a function not written yet, and
    keeps rendering (black or wrong images, exit status 0)."""
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


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
PNG_CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}   # colour type -> samples per pixel
# Adam7 passes: first column, first row, column step, row step.
ADAM7 = ((0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2))


def png_unfilter(ftype, row, prev, step):
    """Undo one scanline's PNG filter in place (prev: the previous scanline, already unfiltered)."""
    n = len(row)
    if ftype == 0:
        return
    if ftype == 1:
        for i in range(step, n):
            row[i] = (row[i] + row[i - step]) & 255
    elif ftype == 2:
        for i in range(n):
            row[i] = (row[i] + prev[i]) & 255
    elif ftype == 3:
        for i in range(n):
            a = row[i - step] if i >= step else 0
            row[i] = (row[i] + ((a + prev[i]) >> 1)) & 255
    elif ftype == 4:
        for i in range(n):
            a = row[i - step] if i >= step else 0
            b = prev[i]
            c = prev[i - step] if i >= step else 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    else:
        raise ValueError(f"unknown PNG filter type {ftype}")


def png_is_black(path):
    """True when every pixel of the PNG is 0 in every colour channel (alpha is not
    a colour), False when some pixel is not. Reads any valid PNG (all colour
    types and bit depths, interlaced or not) with zlib alone; raises ValueError
    for a file it cannot read."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != PNG_SIGNATURE:
        raise ValueError("not a PNG file")
    pos, ihdr, palette, idat = 8, None, None, []
    while pos + 12 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if len(body) != length:
            raise ValueError("truncated PNG chunk")
        pos += 12 + length
        if kind == b"IHDR" and length == 13:
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"PLTE":
            palette = body
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if ihdr is None:
        raise ValueError("PNG without a header (IHDR)")
    width, height, depth, colour, _, _, interlace = ihdr
    channels = PNG_CHANNELS.get(colour)
    if (channels is None or depth not in (1, 2, 4, 8, 16) or (depth < 8 and colour not in (0, 3))
            or (depth == 16 and colour == 3) or interlace > 1):
        raise ValueError(f"unsupported PNG (colour type {colour}, bit depth {depth}, interlace {interlace})")
    if colour == 3 and not palette:
        raise ValueError("palette PNG without a palette (PLTE)")
    try:
        raw = zlib.decompress(b"".join(idat))
    except zlib.error as e:
        raise ValueError(f"bad PNG image data: {e}")
    bits = channels * depth
    step = max(1, bits // 8)                       # the filters' byte distance
    colour_bytes = (3 if colour in (2, 6) else 1) * max(1, depth // 8)
    used = set()                                   # palette indices seen
    pos = 0
    for x0, y0, dx, dy in (ADAM7 if interlace else ((0, 0, 1, 1),)):
        pw = (width - x0 + dx - 1) // dx if width > x0 else 0
        ph = (height - y0 + dy - 1) // dy if height > y0 else 0
        if pw == 0 or ph == 0:
            continue
        stride = (pw * bits + 7) // 8
        prev = bytearray(stride)
        for _ in range(ph):
            if pos + 1 + stride > len(raw):
                raise ValueError("PNG image data too short")
            ftype = raw[pos]
            row = bytearray(raw[pos + 1:pos + 1 + stride])
            pos += 1 + stride
            if any(row) or any(prev) or ftype > 4:     # a zero row after a zero row stays zero
                png_unfilter(ftype, row, prev, step)
            prev = row
            if colour == 3:
                if depth == 8:
                    used.update(row)
                else:
                    mask = (1 << depth) - 1
                    used.update((row[(i * depth) >> 3] >> (8 - depth - (i * depth) % 8)) & mask for i in range(pw))
            elif depth < 8:
                full, rest = divmod(pw * depth, 8)
                if any(row[:full]) or (rest and row[full] >> (8 - rest)):
                    return False
            elif any(any(row[o::step]) for o in range(colour_bytes)):
                return False
    if colour == 3:
        for i in used:
            if 3 * i + 3 > len(palette):
                raise ValueError(f"palette index {i} outside the palette")
            if any(palette[3 * i:3 * i + 3]):
                return False
    return True


def render_checks(entry):
    """What a finished render's files say about it: the TODO lines of its log,
    whether its image is all black, and why the image could not be read."""
    checks = {"todo": todo_lines(os.path.join(entry, "log.txt")), "black": False, "image_error": None}
    try:
        checks["black"] = png_is_black(os.path.join(entry, "render.png"))
    except (OSError, ValueError) as e:
        checks["image_error"] = str(e)
    return checks


def render_problems(r):
    """Why a finished figure needs a look, as (kind, text) pairs: "todo" (a line
    the renderer printed), "black" (every pixel 0, unless the recipe expects
    it), "image" (the PNG could not be read). Empty for a good figure."""
    c = r.job.checks if r.job.status in ("ok", "cached") else None
    if not c:
        return []
    out = [("todo", line) for line in c.get("todo") or []]
    if c.get("black") and not r.expect_black:
        out.append(("black", "the image is all black (every pixel 0)"))
    if c.get("image_error"):
        out.append(("image", f"the image could not be read: {c['image_error']}"))
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


def fmt_duration(s):
    s = int(round(s))
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{(s % 3600) // 60:02d}m"


class Progress:
    """One line per finished render; on a terminal also a live status line."""

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
        self._pending_line = job
        r = job.proto
        what = f"{r.grid}/{r.name}" + (f" (+{len(job.renders) - 1} same)" if len(job.renders) > 1 else "")
        status = "FAILED: " + job.error if job.status == "failed" else f"{job.meta['wall_seconds']:.1f} s, {job.threads} thread(s)"
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
        est = sum(j.est for j in pending if not j.exclusive) / self.budget + sum(j.est for j in pending if j.exclusive)
        self.line(f"{PROG}: {len(pending)} render(s) to run, {n_cached} cached"
                  + (f", {n_dups} shared by several figures" if n_dups else "")
                  + (f"; estimated {fmt_duration(est)} with {self.budget} thread(s)" if pending else ""))


# ---------------------------------------------------------------------------
# The page

def fmt_value(field, v):
    if v is None:
        return "–"
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return html.escape(str(v))
    if isinstance(v, int):
        return f"{v:,}"
    if field.endswith("_seconds"):
        return f"{v:.3f}" if v < 10 else f"{v:.1f}"
    if abs(v) >= 100:
        return f"{v:,.0f}"
    if abs(v) >= 10:
        return f"{v:.1f}"
    return f"{v:.2f}" if abs(v) >= 0.1 else f"{v:.4f}"


def table_cells(table):
    """Rows of (text, numeric) for a table."""
    rows = []
    for row in table["rows"]:
        cells = [(row["scene"], False)]
        for c in table["columns"]:
            if "field" in c:
                r = row["renders"][c.get("variant", table["variants"][0])]
                if r.job.status == "failed":
                    cells.append(("failed", False))
                    continue
                v = r.job.stats.get(c["field"]) if r.job.stats else None
                cells.append((fmt_value(c["field"], v), v is not None))
            else:
                field, a, b = c["ratio"]
                ra, rb = row["renders"][a].job, row["renders"][b].job
                if "failed" in (ra.status, rb.status):
                    cells.append(("failed", False))
                    continue
                va, vb = ra.stats.get(field), rb.stats.get(field)
                if isinstance(va, (int, float)) and isinstance(vb, (int, float)) and vb > 0:
                    x = va / vb
                    cells.append((f"{x:,.0f}×" if x >= 100 else f"{x:.1f}×", True))
                else:
                    cells.append(("–", False))
        rows.append(cells)
    return rows


def figure_info(r, img_dir_rel):
    j = r.job
    base = f"{img_dir_rel}/{r.grid}/{r.name}"
    argv = list(j.meta["argv"]) if j.meta else [display_path(BINARY_FOR_DISPLAY)] + recipe_args(r) + [display_path(r.scene)]
    # Show each figure's own output names (a shared render ran once under neutral names).
    out = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "-f":
            out += ["-f", f"{r.name}.png"]
            i += 2
        elif a == "--stats-json":
            out += ["--stats-json", f"{r.name}.json"]
            i += 2
        else:
            out.append(a)
            i += 1
    info = {"grid": r.grid, "name": r.name, "label": r.label, "status": j.status,
            "command": shlex.join(out), "error": j.error,
            "image": f"{base}.png" if j.status != "failed" else None,
            "rate_image": f"{base}_rate.png" if j.status != "failed" and r.rate else None,
            "render_seconds": j.stats.get("render_seconds") if j.stats else None,
            "wall_seconds": j.meta.get("wall_seconds") if j.meta else None,
            "threads": j.meta.get("threads") if j.meta else None,
            "cached": j.status == "cached",
            "expect_black": r.expect_black,
            "flags": [{"kind": k, "text": t} for k, t in render_problems(r)]}
    return info


BINARY_FOR_DISPLAY = ""

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; background: #f6f6f4;
       max-width: 1240px; margin: 0 auto; padding: 12px 24px 48px; line-height: 1.45; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; }
h2 { margin-top: 2em; border-bottom: 2px solid #ccc; padding-bottom: 4px; }
h3 { margin: 1.6em 0 0.3em; }
p.meta { color: #555; font-size: 0.92em; margin-top: 0; }
.banner { background: #fff3c4; border: 1px solid #e0c060; padding: 8px 12px; border-radius: 6px; }
.errors { background: #fde8e8; border: 1px solid #d08080; padding: 8px 12px; border-radius: 6px; }
nav ul { columns: 2; font-size: 0.95em; }
.grid { display: grid; grid-template-columns: repeat(var(--cols), minmax(0, 1fr)); gap: 14px; }
figure { margin: 0; background: #fff; border: 1px solid #ddd; border-radius: 6px; padding: 8px; }
figure img { max-width: 100%; height: auto; display: block; margin: 0 auto; background: #000; }
.quick figure img { width: 100%; max-width: 320px; image-rendering: pixelated; }
.pair { display: grid; grid-template-columns: 1fr 1fr; gap: 4px; }
.pair span { font-size: 0.8em; color: #666; text-align: center; }
figcaption { margin-top: 6px; font-size: 0.9em; }
figcaption .label { font-weight: 600; }
figcaption .time { color: #666; float: right; }
figcaption code, pre { display: block; font-size: 11px; white-space: pre-wrap; word-break: break-all;
                      background: #f1f1ef; padding: 4px 6px; margin-top: 4px; border-radius: 3px; }
figure.failed { border-color: #d08080; }
.warnings, .warning { background: #fff0d0; border: 1px solid #d09030; padding: 8px 12px; border-radius: 6px;
                      color: #6a3d00; }
.warning { padding: 4px 8px; margin-bottom: 6px; font-size: 0.85em; }
.warning ul, .warnings ul { margin: 2px 0; padding-left: 1.2em; }
.warning code, .warnings code { word-break: break-all; }
figure.flagged { border: 2px solid #d09030; }
table.stats td.flagged { background: #fff0d0; }
.placeholder { aspect-ratio: 4 / 3; background: #fbe3e3; color: #900; display: flex; align-items: center;
               justify-content: center; text-align: center; padding: 8px; font-size: 0.9em; }
table.stats { border-collapse: collapse; background: #fff; font-size: 0.9em; margin: 8px 0; }
table.stats th, table.stats td { border: 1px solid #ccc; padding: 4px 8px; }
table.stats th { background: #eee; }
table.stats td.num { text-align: right; font-variant-numeric: tabular-nums; }
table.stats td.failed { color: #a00; }
details { margin: 6px 0; font-size: 0.9em; }
"""


def write_page(out_dir, recipes, jobs, summary, img_rel="img"):
    figures = []
    tables = []
    h = []
    md = []
    title = recipes.title + (" (quick check)" if recipes.quick else "")
    h.append(f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
             f"<title>{html.escape(title)}</title>\n<style>{CSS}</style>\n</head>\n"
             f"<body class=\"{'quick' if recipes.quick else 'full'}\">\n<h1>{html.escape(title)}</h1>\n")
    run_text = (f"Rendered with `{summary['binary']}` (sha256 {summary['binary_sha256'][:12]}) from "
                f"`{summary['recipes']}`, {summary['date']}: {summary['renders']} figures, "
                f"{summary['distinct_renders']} distinct renders, {summary['rendered']} of them rendered by this "
                f"run in {fmt_duration(summary['wall_seconds'])} with {summary['thread_budget']} thread(s), "
                f"{summary['cached']} from the cache, {summary['failed']} failed, "
                f"{summary['flagged']} figure(s) flagged for checking. "
                + time_text(summary))
    h.append(f"<p class=\"meta\">{inline_md(run_text)}</p>\n")
    md.append(f"# {title}\n\n{run_text}\n\n")
    if recipes.quick:
        q = (f"Quick check (--quick): every image at most {recipes.quick_size[0]}×{recipes.quick_size[1]} "
             f"(a crop of the centre of the view), at most {recipes.quick_max_samples} camera rays and "
             f"{recipes.quick_max_light_samples} light samples. The numbers and images are not the write-up's.")
        h.append(f"<p class=\"banner\">{html.escape(q)}</p>\n")
        md.append(f"> {q}\n\n")
    failed = [j for j in jobs if j.status == "failed"]
    if failed:
        h.append("<div class=\"errors\"><b>Failed renders</b><ul>\n")
        md.append("**Failed renders:**\n\n")
        for j in failed:
            names = ", ".join(f"{r.grid}/{r.name}" for r in j.renders)
            h.append(f"<li><a href=\"#{html.escape(j.renders[0].grid)}\">{html.escape(names)}</a>: "
                     f"{html.escape(j.error)}</li>\n")
            md.append(f"- {names}: {j.error}\n")
        h.append("</ul></div>\n")
        md.append("\n")
    flagged = [(r, render_problems(r)) for r in recipes.renders]
    flagged = [(r, p) for r, p in flagged if p]
    if flagged:
        intro = ("These renders ran to the end, but the renderer printed a TODO line (a function it has not "
                 "written yet) or wrote an all-black image, so the figure is likely not what the write-up "
                 "should show.")
        h.append(f"<div class=\"warnings\" id=\"flagged\"><b>Figures to check ({len(flagged)})</b>: "
                 f"{html.escape(intro)}<ul>\n")
        md.append(f"**Figures to check ({len(flagged)}):** {intro}\n\n")
        for r, problems in flagged:
            name = f"{r.grid}/{r.name}"
            h.append(f"<li><a href=\"#{html.escape(r.grid)}\">{html.escape(name)}</a>: "
                     + "; ".join(problem_html(k, t) for k, t in problems) + "</li>\n")
            md.append(f"- ⚠ {name}: " + "; ".join(problem_md(k, t) for k, t in problems) + "\n")
        h.append("</ul></div>\n")
        md.append("\n")
    h.append("<nav><ul>\n")
    for sec in recipes.sections:
        h.append(f"<li><a href=\"#{sec['id']}\">{html.escape(sec['title'])}</a></li>\n")
    h.append("<li><a href=\"#renders\">All renders and their times</a></li>\n</ul></nav>\n")

    for sec in recipes.sections:
        h.append(f"<section id=\"{sec['id']}\">\n<h2>{html.escape(sec['title'])}</h2>\n")
        md.append(f"## {sec['title']}\n\n")
        if sec["text"]:
            h.append(f"<p>{inline_md(sec['text'])}</p>\n")
            md.append(f"{' '.join(sec['text'].split())}\n\n")
        for item in sec["items"]:
            h.append(f"<h3 id=\"{item['id']}\">{html.escape(item['title'])}</h3>\n")
            md.append(f"### {item['title']}\n\n")
            if item["text"]:
                h.append(f"<p>{inline_md(item['text'])}</p>\n")
                md.append(f"{' '.join(item['text'].split())}\n\n")
            if item["kind"] == "grid":
                page_grid(item, h, md, figures, img_rel)
            else:
                page_table(item, h, md, tables)
        h.append("</section>\n")

    # Every render with its time.
    h.append("<section id=\"renders\">\n<h2>All renders and their times</h2>\n")
    md.append("## All renders and their times\n\n")
    # Time by figure set (each distinct render counted once, where it first appears).
    h.append(f"<p>{inline_md(time_text(summary))}</p>\n")
    md.append(f"{time_text(summary)}\n\n")
    h.append("<table class=\"stats\" id=\"set-times\">\n<tr><th>figure set</th><th>renders</th>"
             "<th>wall × threads</th><th>CPU</th></tr>\n")
    md.append("| figure set | renders | wall × threads | CPU |\n|---|---:|---:|---:|\n")
    seen = set()
    for sec in recipes.sections:
        for item in sec["items"]:
            rs = item["renders"] if item["kind"] == "grid" else [r for row in item["rows"] for r in row["renders"].values()]
            mine = []
            for r in rs:
                if r.job.key not in seen:
                    seen.add(r.job.key)
                    mine.append(r.job)
            wt, cpu = job_times(mine)
            h.append(f"<tr><td><a href=\"#{item['id']}\">{html.escape(item['title'])}</a></td>"
                     f"<td class=\"num\">{len(rs)}</td><td class=\"num\">{fmt_duration(wt)}</td>"
                     f"<td class=\"num\">{fmt_duration(cpu) if cpu is not None else '–'}</td></tr>\n")
            md.append(f"| {item['title']} | {len(rs)} | {fmt_duration(wt)} | "
                      f"{fmt_duration(cpu) if cpu is not None else '–'} |\n")
    cpu = summary["cpu_seconds"]
    h.append(f"<tr><th>total</th><th class=\"num\">{len(recipes.renders)}</th>"
             f"<th class=\"num\">{fmt_duration(summary['wall_thread_seconds'])}</th>"
             f"<th class=\"num\">{fmt_duration(cpu) if cpu is not None else '–'}</th></tr>\n</table>\n")
    md.append(f"| **total** | {len(recipes.renders)} | {fmt_duration(summary['wall_thread_seconds'])} | "
              f"{fmt_duration(cpu) if cpu is not None else '–'} |\n\n")
    h.append("<p>Per render: <i>render</i> is the renderer's own render time (without loading the scene and "
             "building the BVH); <i>wall</i> the whole process and <i>CPU</i> its user + system time, as "
             "measured by the generator when it ran; cached renders show the times of the run that made "
             "them. Status <i>check</i>: the render is flagged (see the list at the head of the page).</p>\n")
    h.append("<table class=\"stats\" id=\"render-times\">\n<tr><th>figure</th><th>status</th>"
             "<th>render s</th><th>wall s</th><th>CPU s</th><th>threads</th><th>rendered</th></tr>\n")
    md.append("| figure | status | render s | wall s | CPU s | threads | rendered |\n|---|---|---:|---:|---:|---:|---|\n")
    for r in recipes.renders:
        j = r.job
        rs = j.stats.get("render_seconds") if j.stats else None
        ws = j.meta.get("wall_seconds") if j.meta else None
        cs = j.meta.get("cpu_seconds") if j.meta else None
        th = j.meta.get("threads") if j.meta else None
        when = "failed" if j.status == "failed" else ("cached" if j.status == "cached" else "this run")
        ok = "failed" if j.status == "failed" else ("check" if render_problems(r) else "ok")
        h.append(f"<tr><td><a href=\"#{r.grid}\">{html.escape(r.grid + '/' + r.name)}</a></td>"
                 f"<td class=\"{'failed' if ok == 'failed' else ('flagged' if ok == 'check' else '')}\">{ok}</td>"
                 f"<td class=\"num\">{fmt_value('render_seconds', rs)}</td>"
                 f"<td class=\"num\">{fmt_value('wall_seconds', ws)}</td>"
                 f"<td class=\"num\">{fmt_value('cpu_seconds', cs)}</td>"
                 f"<td class=\"num\">{th if th is not None else '–'}</td><td>{when}</td></tr>\n")
        md.append(f"| {r.grid}/{r.name} | {ok} | {fmt_value('render_seconds', rs)} | "
                  f"{fmt_value('wall_seconds', ws)} | {fmt_value('cpu_seconds', cs)} | "
                  f"{th if th is not None else '–'} | {when} |\n")
    h.append("</table>\n</section>\n</body>\n</html>\n")
    md.append("\n")
    write_atomically(os.path.join(out_dir, "index.html"), "".join(h))
    write_atomically(os.path.join(out_dir, "index.md"), "".join(md))
    manifest = {"summary": summary, "figures": figures, "tables": tables}
    write_atomically(os.path.join(out_dir, "manifest.json"), json.dumps(manifest, indent=1) + "\n")


def job_times(jobs):
    """Sum of wall time x threads, and of CPU time (None if a render lacks it), over successful jobs."""
    wt, cpu = 0.0, 0.0
    for j in jobs:
        if j.meta and j.status != "failed":
            wt += j.meta["wall_seconds"] * j.meta.get("threads", 1)
            c = j.meta.get("cpu_seconds")
            cpu = None if cpu is None or c is None else cpu + c
    return wt, cpu


def time_text(summary):
    cpu = summary["cpu_seconds"]
    text = (f"All renders together took {fmt_duration(summary['wall_thread_seconds'])} of wall time × threads")
    if cpu is not None:
        text += (f" and {fmt_duration(cpu)} of CPU time: from scratch, on {summary['thread_budget']} otherwise idle "
                 f"core(s), the page would take about {fmt_duration(summary['idle_estimate_seconds'])}")
    return text + "."


def inline_md(text):
    """The recipes' text: `code` spans, paragraphs split at blank lines."""
    parts = re.split(r"`([^`]*)`", " ".join(text.split()))
    return "".join(f"<code class=\"inline\">{html.escape(p)}</code>" if i % 2 else html.escape(p)
                   for i, p in enumerate(parts))


def page_grid(grid, h, md, figures, img_rel):
    cols = grid["columns"]
    h.append(f"<div class=\"grid\" style=\"--cols: {cols}\">\n")
    cells_md = []
    for r in grid["renders"]:
        f = figure_info(r, img_rel)
        f["rate"] = grid["rate"]
        figures.append(f)
        label = html.escape(f["label"])
        if f["status"] == "failed":
            h.append(f"<figure class=\"failed\" data-status=\"failed\"><div class=\"placeholder\">render failed:<br>"
                     f"{html.escape(f['error'])}</div>\n")
            timing = "failed"
            cells_md.append(f"**{f['label']}**<br>FAILED: {f['error']}<br>`{f['command']}`")
        else:
            img = f"<a href=\"{f['image']}\"><img src=\"{f['image']}\" alt=\"{label}\"></a>"
            if grid["rate"]:
                img = (f"<div class=\"pair\">{img}<a href=\"{f['rate_image']}\"><img src=\"{f['rate_image']}\" "
                       f"alt=\"{label}: sampling rate\"></a><span>render</span><span>sampling rate</span></div>")
            problems = render_problems(r)
            if problems:
                kinds = " ".join(dict.fromkeys(k for k, _ in problems))
                h.append(f"<figure class=\"flagged\" data-status=\"ok\" data-flagged=\"{kinds}\">"
                         f"<div class=\"warning\"><b>⚠ Check this figure:</b><ul>"
                         + "".join(f"<li>{problem_html(k, t)}</li>" for k, t in problems)
                         + f"</ul></div>{img}\n")
            else:
                h.append(f"<figure data-status=\"ok\">{img}\n")
            rs = f["render_seconds"]
            timing = (f"{fmt_value('render_seconds', rs)} s, {f['threads']} thread{'s' if f['threads'] != 1 else ''}"
                      if rs is not None else "")
            imgs_md = f"![{f['label']}]({f['image']})"
            if grid["rate"]:
                imgs_md += f" ![{f['label']}: sampling rate]({f['rate_image']})"
            warn_md = ("**⚠ Check this figure:** " + "; ".join(problem_md(k, t) for k, t in problems) + "<br>"
                       if problems else "")
            cells_md.append(f"{warn_md}{imgs_md}<br>**{f['label']}** ({timing})<br>`{f['command']}`")
        h.append(f"<figcaption><span class=\"label\">{label}</span> <span class=\"time\">{html.escape(timing)}</span>"
                 f"<code>{html.escape(f['command'])}</code></figcaption></figure>\n")
    h.append("</div>\n")
    for i in range(0, len(cells_md), cols):
        row = cells_md[i:i + cols]
        if i == 0:
            md.append("|" + " |" * cols + "\n|" + "---|" * cols + "\n")
        md.append("| " + " | ".join(row + [""] * (cols - len(row))) + " |\n")
    md.append("\n")


def table_flagged(table):
    """Rows of yes/no for a table's cells: whether a render the cell reads is flagged."""
    out = []
    for row in table["rows"]:
        cells = [False]
        for c in table["columns"]:
            names = [c.get("variant", table["variants"][0])] if "field" in c else c["ratio"][1:]
            cells.append(any(render_problems(row["renders"][v]) for v in names))
        out.append(cells)
    return out


def table_conditions(table):
    """How a table's renders ran, from the renders themselves: size, threads, alone or not."""
    rs = [r for row in table["rows"] for r in row["renders"].values() if r.job.status != "failed"]
    if not rs:
        return ""
    sizes = sorted({r.size for r in rs})
    threads = sorted({r.job.meta["threads"] for r in rs if r.job.meta and r.job.meta.get("threads")})
    text = "Rendered at " + ", ".join(f"{w} × {h}" for w, h in sizes)
    if threads:
        n = f"{threads[0]}" if len(threads) == 1 else f"{threads[0]} to {threads[-1]}"
        text += f", on {n} thread{'s' if threads[-1] != 1 else ''} each"
    if all(r.exclusive for r in rs):
        text += ", each render alone (no other render of the generator running beside it)."
    else:
        text += (", beside other renders of the generator"
                 + (" (--quick does not run timing renders alone)" if any(r.quick_exclusive for r in rs) else "")
                 + ": the times are rougher.")
    return text


def page_table(table, h, md, tables):
    heads = ["scene"] + [c["title"] for c in table["columns"]]
    rows = table_cells(table)
    marks = table_flagged(table)
    tables.append({"id": table["id"], "title": table["title"], "columns": heads,
                   "rows": [[t for t, _ in row] for row in rows],
                   "numeric": [[n for _, n in row] for row in rows]})
    h.append(f"<table class=\"stats\" id=\"table-{table['id']}\">\n<tr>"
             + "".join(f"<th>{html.escape(x)}</th>" for x in heads) + "</tr>\n")
    for row, flags in zip(rows, marks):
        h.append("<tr>" + "".join(
            f"<td class=\"{'num' if n else ('failed' if t == 'failed' else '')}{' flagged' if x else ''}\">"
            f"{html.escape(t)}</td>"
            for (t, n), x in zip(row, flags)) + "</tr>\n")
    h.append("</table>\n")
    md.append("| " + " | ".join(heads) + " |\n|---|" + "---:|" * (len(heads) - 1) + "\n")
    for row, flags in zip(rows, marks):
        md.append("| " + " | ".join(t + (" ⚠" if x else "") for (t, _), x in zip(row, flags)) + " |\n")
    md.append("\n")
    cmds = []
    errors = []
    checks = []
    for row in table["rows"]:
        for r in row["renders"].values():
            f = figure_info(r, "img")
            cmds.append(f["command"])
            if f["status"] == "failed":
                errors.append(f"{row['scene']}, {r.label}: {f['error']}")
            problems = render_problems(r)
            if problems:
                checks.append((r, problems))
    conditions = table_conditions(table)
    if conditions:
        h.append(f"<p class=\"meta\">{html.escape(conditions)}</p>\n")
        md.append(f"{conditions}\n\n")
    for e in errors:
        h.append(f"<p class=\"errors\">render failed: {html.escape(e)}</p>\n")
        md.append(f"- render failed: {e}\n")
    for r, problems in checks:
        h.append(f"<p class=\"warning\" data-flagged=\"{' '.join(dict.fromkeys(k for k, _ in problems))}\">"
                 f"<b>⚠ Check</b> {html.escape(r.label)}: "
                 + "; ".join(problem_html(k, t) for k, t in problems) + "</p>\n")
        md.append(f"- ⚠ Check {r.label}: " + "; ".join(problem_md(k, t) for k, t in problems) + "\n")
    if errors or checks:
        md.append("\n")
    h.append(f"<details><summary>The {len(cmds)} commands</summary><pre>"
             + html.escape("\n".join(cmds)) + "</pre></details>\n")
    md.append("<details><summary>The commands</summary>\n\n```\n" + "\n".join(cmds) + "\n```\n\n</details>\n\n")


def write_atomically(path, text):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


# ---------------------------------------------------------------------------

def main(argv=None):
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
    a = ap.parse_args(argv)

    try:
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
            pats = [p.strip() for p in a.only.split(",") if p.strip()]
            all_ids = [it["id"] for s in recipes.sections for it in s["items"]]
            for p in pats:
                if not any(fnmatch.fnmatchcase(i, p) for i in all_ids):
                    raise InputError(f"--only: no grid or table matches '{p}' in {recipes.display}")
            for s in recipes.sections:
                s["items"] = [it for it in s["items"] if any(fnmatch.fnmatchcase(it["id"], p) for p in pats)]
            recipes.sections = [s for s in recipes.sections if s["items"]]
            keep = {it["id"] for s in recipes.sections for it in s["items"]}
            recipes.renders = [r for r in recipes.renders if r.grid in keep]
    except InputError as e:
        sys.stderr.write(f"{PROG}: error: {e}\n")
        return 2

    global BINARY_FOR_DISPLAY
    BINARY_FOR_DISPLAY = binary
    out_dir = os.path.abspath(a.out or os.path.join(ROOT, "writeup", "out", "quick" if a.quick else ""))
    cache_dir = os.path.abspath(a.cache) if a.cache else os.path.join(out_dir, "cache")
    binary_hash = file_hash(binary)

    # One job per distinct render; a render several figures share runs once.
    jobs = {}
    for r in recipes.renders:
        key = cache_key(r, binary_hash)
        if key in jobs:
            jobs[key].renders.append(r)
            jobs[key].exclusive = jobs[key].exclusive or r.exclusive
        else:
            jobs[key] = Job(key, r)
        r.job = jobs[key]
    jobs = list(jobs.values())

    history_path = os.path.join(cache_dir, "history.json")
    try:
        with open(history_path) as f:
            history = json.load(f)
    except (OSError, ValueError):
        history = {}
    pending = []
    for j in jobs:
        entry = os.path.join(cache_dir, j.key)
        if not a.force and os.path.isfile(os.path.join(entry, "meta.json")):
            try:
                with open(os.path.join(entry, "meta.json")) as f:
                    j.meta = json.load(f)
                with open(os.path.join(entry, "render.json")) as f:
                    j.stats = json.load(f)
                if os.path.isfile(os.path.join(entry, "render.png")):
                    j.status, j.dir = "cached", entry
                    j.checks = j.meta.get("checks")
                    if not isinstance(j.checks, dict):  # an entry made before the checks were kept
                        j.checks = render_checks(entry)
                    continue
            except (OSError, ValueError):
                j.meta = j.stats = None
        j.est = history.get(command_key(j.proto)) or cost_units(j.proto)
        pending.append(j)

    if a.dry_run:
        for r in recipes.renders:
            j = r.job
            state = "cached" if j.status == "cached" else "to render"
            print(f"{state:9} {r.grid}/{r.name}: {shlex.join([display_path(binary)] + recipe_args(r) + [display_path(r.scene)])}")
        return 0

    os.makedirs(cache_dir, exist_ok=True)
    # Render with a private copy of the binary, so that a rebuild during the
    # run cannot put another binary's images under this one's cache keys.
    run_binary = binary
    if pending:
        bin_dir = os.path.join(cache_dir, "bin")
        os.makedirs(bin_dir, exist_ok=True)
        run_binary = os.path.join(bin_dir, f"pathtracer-{binary_hash[:16]}")
        if not os.path.isfile(run_binary) or file_hash(run_binary) != binary_hash:
            tmp = f"{run_binary}.tmp.{os.getpid()}"
            shutil.copyfile(binary, tmp)
            os.chmod(tmp, 0o755)
            os.replace(tmp, run_binary)
            if file_hash(run_binary) != binary_hash:
                sys.stderr.write(f"{PROG}: error: {display_path(binary)} changed while it was being copied; "
                                 f"run again when the build has finished\n")
                return 2
    progress = Progress(pending, a.threads, not a.no_progress)
    progress.plan(len(jobs) - len(pending), len(recipes.renders) - len(jobs), pending)
    t0 = time.monotonic()
    sched = Scheduler(pending, run_binary, cache_dir, a.threads, a.timeout, history, progress)
    sched.display_binary = binary
    try:
        sched.run()
    except KeyboardInterrupt:
        sys.stderr.write(f"\n{PROG}: interrupted; finished renders are cached\n")
        write_atomically(history_path, json.dumps(history, indent=0, sort_keys=True))
        return 130
    wall = time.monotonic() - t0
    write_atomically(history_path, json.dumps(history, indent=0, sort_keys=True))

    # Images into OUT/img/<grid>/<name>.png.
    img_dir = os.path.join(out_dir, "img")
    shutil.rmtree(img_dir, ignore_errors=True)
    for r in recipes.renders:
        j = r.job
        if j.status == "failed":
            continue
        os.makedirs(os.path.join(img_dir, r.grid), exist_ok=True)
        for src, dst in (("render.png", f"{r.name}.png"),) + ((("render_rate.png", f"{r.name}_rate.png"),) if r.rate else ()):
            s = os.path.join(j.dir, src)
            if os.path.isfile(s):
                shutil.copyfile(s, os.path.join(img_dir, r.grid, dst))

    failed = [j for j in jobs if j.status == "failed"]
    flagged = [(r, render_problems(r)) for r in recipes.renders]
    flagged = [(r, p) for r, p in flagged if p]
    summary = {
        "binary": display_path(binary), "binary_sha256": binary_hash,
        "recipes": recipes.display, "quick": recipes.quick,
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "renders": len(recipes.renders), "distinct_renders": len(jobs),
        "rendered": len(pending), "cached": len(jobs) - len(pending), "failed": len(failed),
        "flagged": len(flagged), "wall_seconds": round(wall, 2), "thread_budget": a.threads,
    }
    wt, cpu = job_times(jobs)
    summary["wall_thread_seconds"] = round(wt, 1)
    summary["cpu_seconds"] = round(cpu, 1) if cpu is not None else None
    # Timing renders run alone; the rest share the thread budget.
    _, cpu_x = job_times([j for j in jobs if j.exclusive])
    summary["idle_estimate_seconds"] = (round(cpu_x + (cpu - cpu_x) / a.threads, 1)
                                        if cpu is not None and cpu_x is not None else None)
    write_page(out_dir, recipes, jobs, summary)

    if a.prune:
        used = {j.key for j in jobs}
        removed = 0
        for name in os.listdir(cache_dir):
            p = os.path.join(cache_dir, name)
            if re.fullmatch(r"[0-9a-f]{32}", name) and name not in used and os.path.isdir(p):
                shutil.rmtree(p, ignore_errors=True)
                removed += 1
        shutil.rmtree(os.path.join(cache_dir, "failed"), ignore_errors=True)
        if not a.no_progress:
            sys.stderr.write(f"{PROG}: pruned {removed} unused cache entries\n")

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
    return 1 if failed else (3 if flagged else 0)


if __name__ == "__main__":
    sys.exit(main())
