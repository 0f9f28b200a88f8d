"""The render cache: OUT/cache/<key>/ holds one finished render (render.png,
render_rate.png, render.json from --stats-json, log.txt, meta.json with the
command, times and checks, and render_env_probability.png when its grid shows
where the environment map is sampled); failed renders go to OUT/cache/failed/<key>/;
history.json keeps each recipe's last CPU time for the ETA; bin/ the private
copy of the binary renders run with."""

import hashlib
import json
import os
import re
import shutil

from . import checks
from .base import display_path, write_atomically
from .flags import FILE_FLAGS, get_flag, recipe_args


class FileHashes:
    """SHA-256 of files, each read once per size and modification time."""

    def __init__(self):
        self._known = {}

    def __call__(self, path):
        st = os.stat(path)
        key = (path, st.st_size, st.st_mtime_ns)
        if key not in self._known:
            h = hashlib.sha256()
            with open(path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    h.update(block)
            self._known[key] = h.hexdigest()
        return self._known[key]


def command_key(r):
    """Identifies the recipe without the binary: for the timing history."""
    parts = recipe_args(r) + [display_path(r.scene)]
    if r.threads is not None:
        parts += ["-t", str(r.threads)]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:24]


def cache_key(r, binary_hash, file_hash):
    """The command line (without -t unless the recipe fixes it, and without output
    paths), the binary's bytes, and the bytes of the files the command reads."""
    files = [file_hash(r.scene)] + [file_hash(get_flag(r.flags, f)[0]) for f in FILE_FLAGS if get_flag(r.flags, f)]
    what = {"args": recipe_args(r), "threads": r.threads, "binary": binary_hash,
            "scene": os.path.basename(r.scene), "files": files}
    if r.env_probability:
        what["env_probability"] = True  # the entry holds that image too
    if r.preview > 1:
        what["preview"] = r.preview  # the entry's PNG is the render shrunk this many times
    desc = json.dumps(what)
    return hashlib.sha256(desc.encode()).hexdigest()[:32]


def entry_images(r):
    """The images a finished render's entry holds for render r: render.png and,
    when its grid shows it, render_env_probability.png (render_rate.png is
    always written, and only shown)."""
    return ["render.png"] + (["render_env_probability.png"] if r.env_probability else [])


class Cache:
    def __init__(self, directory):
        self.dir = directory
        self.history_path = os.path.join(directory, "history.json")

    def load_history(self):
        try:
            with open(self.history_path) as f:
                return json.load(f)
        except (OSError, ValueError):
            return {}

    def save_history(self, history):
        write_atomically(self.history_path, json.dumps(history, indent=0, sort_keys=True))

    def lookup(self, job):
        """Fills job from its cache entry and returns True when there is a usable one:
        meta.json, render.json and its images (entry_images). The checks come from meta.json, or
        again from the entry's log and render.json when they are not there."""
        entry = os.path.join(self.dir, job.key)
        if not os.path.isfile(os.path.join(entry, "meta.json")):
            return False
        try:
            with open(os.path.join(entry, "meta.json")) as f:
                job.meta = json.load(f)
            with open(os.path.join(entry, "render.json")) as f:
                job.stats = json.load(f)
            if all(os.path.isfile(os.path.join(entry, f)) for f in entry_images(job.proto)):
                job.status, job.dir = "cached", entry
                job.checks = job.meta.get("checks")
                if not checks.current(job.checks):
                    job.checks = checks.entry_checks(entry, job.stats)
                return True
        except (OSError, ValueError):
            pass
        job.meta = job.stats = None
        return False

    def new_entry(self, key):
        """An empty folder for a render to write into (made into an entry by store)."""
        tmp = os.path.join(self.dir, f"{key}.tmp-{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
        return tmp

    def store(self, job, tmp):
        """A finished render's folder becomes its entry, with meta.json."""
        with open(os.path.join(tmp, "meta.json"), "w") as f:
            json.dump(job.meta, f, indent=1)
        final = os.path.join(self.dir, job.key)
        shutil.rmtree(final, ignore_errors=True)
        os.replace(tmp, final)
        return final

    def store_failed(self, job, tmp):
        """A failed render's folder goes under failed/ (not an entry: it is tried again)."""
        failed_dir = os.path.join(self.dir, "failed", job.key)
        shutil.rmtree(failed_dir, ignore_errors=True)
        os.makedirs(os.path.dirname(failed_dir), exist_ok=True)
        os.replace(tmp, failed_dir)
        return failed_dir

    def private_binary(self, binary, binary_hash, file_hash):
        """A copy of the binary under bin/, named by its hash, so that a rebuild
        during the run cannot put another binary's images under this one's keys.
        None when the binary changed while it was being copied."""
        bin_dir = os.path.join(self.dir, "bin")
        os.makedirs(bin_dir, exist_ok=True)
        run_binary = os.path.join(bin_dir, f"pathtracer-{binary_hash[:16]}")
        if not os.path.isfile(run_binary) or file_hash(run_binary) != binary_hash:
            tmp = f"{run_binary}.tmp.{os.getpid()}"
            shutil.copyfile(binary, tmp)
            os.chmod(tmp, 0o755)
            os.replace(tmp, run_binary)
            if file_hash(run_binary) != binary_hash:
                return None
        return run_binary

    def prune(self, used):
        """Deletes the entries whose keys are not in used, and failed/; returns how many entries went."""
        removed = 0
        for name in os.listdir(self.dir):
            p = os.path.join(self.dir, name)
            if re.fullmatch(r"[0-9a-f]{32}", name) and name not in used and os.path.isdir(p):
                shutil.rmtree(p, ignore_errors=True)
                removed += 1
        shutil.rmtree(os.path.join(self.dir, "failed"), ignore_errors=True)
        return removed
