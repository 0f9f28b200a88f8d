#!/usr/bin/env python3
"""Unit tests of writeup/generator/cache.py: what a cache key depends on (the
command without -t and output names, the binary's bytes, the scene's and the
-e/-c files' bytes) and what it does not; cache entries found, refused,
stored, checked again when made by an earlier generator, pruned; the
private copy of the binary."""

import json
import os
import shutil
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import import_generator  # noqa: E402

import_generator()
from generator import cache  # noqa: E402
from generator.flags import parse_flags  # noqa: E402
from generator.recipes import Render  # noqa: E402
from generator.scheduler import Job  # noqa: E402


class CacheTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="writeup-cache-unit-")
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.scene = self.file("scene.dae", "<COLLADA/>")
        self.env = self.file("sky.exr", "sky")

    def file(self, name, text):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def render(self, args="--part 3 -s 4", size=(32, 24), seed=1, threads=None, scene=None, name="a"):
        return Render(where="w", grid="g", name=name, label=name, scene=scene or self.scene,
                      flags=parse_flags(args, "w"), size=size, seed=seed, threads=threads,
                      exclusive=False, quick_exclusive=False)

    def key(self, r, binary="b" * 64, hashes=None):
        return cache.cache_key(r, binary, hashes or cache.FileHashes())

    def test_key_follows_what_decides_the_image(self):
        base = self.key(self.render())
        self.assertRegex(base, r"^[0-9a-f]{32}$")
        self.assertEqual(self.key(self.render(name="other figure")), base)       # shared by figures alike
        for changed in (self.render(args="--part 3 -s 8"), self.render(size=(32, 25)), self.render(seed=2),
                        self.render(threads=2), self.render(args=f"--part 3 -s 4 -e {self.env}")):
            self.assertNotEqual(self.key(changed), base)
        self.assertNotEqual(self.key(self.render(), binary="c" * 64), base)
        # A --quick preview's entry holds the render shrunk: another factor, another image.
        shrunk = self.render()
        shrunk.preview = 4
        self.assertNotEqual(self.key(shrunk), base)
        shrunk.preview = 1
        self.assertEqual(self.key(shrunk), base)
        # The same scene name with other bytes, and other bytes in the -e file.
        with_env = self.key(self.render(args=f"--part 3 -s 4 -e {self.env}"))
        with open(self.env, "a") as f:
            f.write("!")
        self.assertNotEqual(self.key(self.render(args=f"--part 3 -s 4 -e {self.env}")), with_env)
        with open(self.scene, "a") as f:
            f.write("<!-- -->")
        self.assertNotEqual(self.key(self.render()), base)

    def test_threads_only_when_the_recipe_fixes_them(self):
        # The scheduler picks -t freely: a render's key has no -t unless the recipe sets threads.
        self.assertEqual(self.key(self.render(threads=None)), self.key(self.render(threads=None)))
        self.assertNotEqual(self.key(self.render(threads=1)), self.key(self.render(threads=4)))

    def test_command_key_leaves_out_the_binary(self):
        r = self.render()
        self.assertEqual(cache.command_key(r), cache.command_key(self.render(name="b")))
        self.assertNotEqual(cache.command_key(r), cache.command_key(self.render(seed=5)))

    def test_file_hashes_notice_a_change(self):
        hashes = cache.FileHashes()
        h1 = hashes(self.scene)
        self.assertEqual(hashes(self.scene), h1)
        with open(self.scene, "a") as f:
            f.write("more")
        self.assertNotEqual(hashes(self.scene), h1)

    def entry(self, c, key, meta=True, stats=True, png=True, checks=None):
        d = os.path.join(c.dir, key)
        os.makedirs(d)
        if meta:
            with open(os.path.join(d, "meta.json"), "w") as f:
                json.dump({"threads": 1, "wall_seconds": 1.0, **({"checks": checks} if checks else {})}, f)
        if stats:
            with open(os.path.join(d, "render.json"), "w") as f:
                json.dump({"render_seconds": 0.5, "max_radiance": 0}, f)
        if png:
            open(os.path.join(d, "render.png"), "wb").close()
        with open(os.path.join(d, "log.txt"), "w") as f:
            f.write("TODO: implement x (y.cpp)\n")
        return d

    def test_lookup(self):
        c = cache.Cache(os.path.join(self.tmp, "cache"))
        kept = {"todo": [], "max_radiance": 2.0, "black": False, "image_error": None}
        self.entry(c, "a" * 32, checks=kept)
        self.entry(c, "b" * 32, checks={"todo": [], "black": False, "image_error": None})  # an earlier generator's
        self.entry(c, "c" * 32, png=False)
        self.entry(c, "d" * 32, stats=False)
        jobs = {k: Job(k * 32, self.render()) for k in "abcde"}
        found = {k: c.lookup(j) for k, j in jobs.items()}
        self.assertEqual(found, {"a": True, "b": True, "c": False, "d": False, "e": False})
        self.assertEqual((jobs["a"].status, jobs["a"].checks, jobs["a"].stats["render_seconds"]),
                         ("cached", kept, 0.5))
        self.assertEqual(jobs["a"].dir, os.path.join(c.dir, "a" * 32))
        # Checks without max_radiance are made again from the entry's render.json and log.
        self.assertEqual(jobs["b"].checks, {"todo": ["TODO: implement x (y.cpp)"], "max_radiance": 0.0,
                                            "black": True, "image_error": None})
        for k in "cde":
            self.assertIsNone(jobs[k].status)
            self.assertIsNone(jobs[k].meta)

    def test_store_prune_and_history(self):
        c = cache.Cache(os.path.join(self.tmp, "cache"))
        os.makedirs(c.dir)
        job = Job("e" * 32, self.render())
        job.meta = {"threads": 2}
        tmp = c.new_entry(job.key)
        open(os.path.join(tmp, "render.png"), "wb").close()
        final = c.store(job, tmp)
        self.assertEqual(final, os.path.join(c.dir, job.key))
        with open(os.path.join(final, "meta.json")) as f:
            self.assertEqual(json.load(f), {"threads": 2})
        self.assertFalse(os.path.exists(tmp))
        failed = Job("f" * 32, self.render())
        tmp = c.new_entry(failed.key)
        self.assertEqual(c.store_failed(failed, tmp), os.path.join(c.dir, "failed", failed.key))
        self.entry(c, "0" * 32)
        os.makedirs(os.path.join(c.dir, "bin"))
        c.save_history({"k": 1.5})
        self.assertEqual(c.load_history(), {"k": 1.5})
        self.assertEqual(c.prune({job.key}), 1)
        self.assertEqual(sorted(os.listdir(c.dir)), sorted(["bin", job.key, "history.json"]))
        self.assertEqual(cache.Cache(os.path.join(self.tmp, "none")).load_history(), {})

    def test_private_binary(self):
        c = cache.Cache(os.path.join(self.tmp, "cache"))
        binary = self.file("pathtracer", "#!/bin/sh\n")
        hashes = cache.FileHashes()
        h = hashes(binary)
        copy = c.private_binary(binary, h, hashes)
        self.assertEqual(copy, os.path.join(c.dir, "bin", f"pathtracer-{h[:16]}"))
        self.assertEqual(hashes(copy), h)
        self.assertTrue(os.access(copy, os.X_OK))
        # A binary that no longer has the bytes it was hashed with: no copy.
        self.assertIsNone(c.private_binary(binary, "0" * 64, hashes))


if __name__ == "__main__":
    unittest.main()
