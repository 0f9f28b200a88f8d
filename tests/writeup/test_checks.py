#!/usr/bin/env python3
"""Unit tests of writeup/generator/checks.py: TODO lines from a render's log,
the all-black flag from the renderer's max_radiance (never from the PNG),
expect_black, and the problems a figure is flagged for."""

import json
import os
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import import_generator  # noqa: E402

import_generator()
from generator import checks  # noqa: E402

TODO = "TODO: implement Part 1: generate_ray (stages/part1_raytracing/camera_rays.cpp)"


class Job:
    def __init__(self, status, checks=None):
        self.status, self.checks = status, checks


class Figure:
    def __init__(self, job, expect_black=False):
        self.job, self.expect_black = job, expect_black


class ChecksTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(prefix="writeup-checks-")
        self.addCleanup(self.tmp.cleanup)
        self.log = os.path.join(self.tmp.name, "log.txt")

    def write_log(self, text):
        with open(self.log, "w") as f:
            f.write(text)

    def test_todo_lines(self):
        self.write_log("[PathTracer] Rendering... \n"
                       f"pathtracer: {TODO}\n"
                       "NOTODO: not one\nmy_TODO: nor this\n"
                       f"{TODO}\n"                      # the same line again: listed once
                       "  TODO: implement Part 3: x (y.cpp)  \n")
        self.assertEqual(checks.todo_lines(self.log), [TODO, "TODO: implement Part 3: x (y.cpp)"])
        self.assertEqual(checks.todo_lines(os.path.join(self.tmp.name, "missing.txt")), [])

    def test_black_comes_from_max_radiance(self):
        self.write_log("")
        for stats, black in (({"max_radiance": 0}, True), ({"max_radiance": 0.0}, True),
                             ({"max_radiance": -1.0}, True),
                             ({"max_radiance": 1.4e-45}, False), ({"max_radiance": 10}, False)):
            c = checks.make_checks(self.log, stats)
            self.assertEqual((c["black"], c["image_error"]), (black, None), stats)
            self.assertEqual(c["max_radiance"], float(stats["max_radiance"]))

    def test_no_max_radiance_cannot_be_checked(self):
        self.write_log("")
        for stats, words in ((None, "no max_radiance"), ({"render_seconds": 1.0}, "no max_radiance"),
                             ({"max_radiance": "0"}, "not a number"), ({"max_radiance": True}, "not a number"),
                             ({"max_radiance": float("nan")}, "not a number")):
            c = checks.make_checks(self.log, stats)
            self.assertFalse(c["black"])
            self.assertIn(words, c["image_error"])
            problems = checks.render_problems(Figure(Job("ok", c)))
            self.assertEqual([k for k, _ in problems], ["image"])
            self.assertIn("could not be checked", problems[0][1])

    def test_entry_checks_read_the_cache_entry(self):
        self.write_log(f"{TODO}\n")
        with open(os.path.join(self.tmp.name, "render.json"), "w") as f:
            json.dump({"max_radiance": 0}, f)
        # A PNG that is not black at all: the check does not look at it.
        with open(os.path.join(self.tmp.name, "render.png"), "wb") as f:
            f.write(b"not even a PNG")
        c = checks.entry_checks(self.tmp.name)
        self.assertEqual(c, {"todo": [TODO], "max_radiance": 0.0, "black": True, "image_error": None})
        self.assertTrue(checks.current(c))
        # Checks kept by an earlier generator (no max_radiance) are not current.
        self.assertFalse(checks.current({"todo": [], "black": True, "image_error": None}))
        self.assertFalse(checks.current(None))

    def test_render_problems(self):
        black_todo = {"todo": [TODO], "max_radiance": 0.0, "black": True, "image_error": None}
        lit = {"todo": [], "max_radiance": 0.5, "black": False, "image_error": None}
        self.assertEqual(checks.render_problems(Figure(Job("ok", black_todo))),
                         [("todo", TODO), ("black", "the image is all black (every pixel 0)")])
        # expect_black takes the black flag away, not the TODO line.
        self.assertEqual(checks.render_problems(Figure(Job("cached", black_todo), expect_black=True)),
                         [("todo", TODO)])
        self.assertEqual(checks.render_problems(Figure(Job("ok", lit))), [])
        self.assertEqual(checks.render_problems(Figure(Job("failed", black_todo))), [])
        # --quick: a preview of one colour shows nothing, lit or not; the
        # black flag, when there is one, says it already.
        flat = dict(lit, preview={"width": 120, "height": 90, "flat": True, "color": [0, 0, 0]})
        self.assertEqual(checks.render_problems(Figure(Job("ok", flat))),
                         [("flat", "the preview shows nothing: every pixel is black")])
        grey = dict(lit, preview={"width": 120, "height": 90, "flat": True, "color": [12, 12, 40]})
        self.assertEqual(checks.render_problems(Figure(Job("cached", grey))),
                         [("flat", "the preview shows nothing: every pixel is the same colour, 12 12 40")])
        self.assertEqual(checks.render_problems(Figure(Job("ok", grey), expect_black=True)), [])
        self.assertEqual(checks.render_problems(Figure(Job("ok", dict(black_todo, preview=flat["preview"])))),
                         [("todo", TODO), ("black", "the image is all black (every pixel 0)")])
        shows = dict(lit, preview={"width": 120, "height": 90, "flat": False, "color": [0, 0, 0]})
        self.assertEqual(checks.render_problems(Figure(Job("ok", shows))), [])

    def test_problem_texts(self):
        self.assertEqual(checks.problem_text("todo", TODO), f"the renderer printed '{TODO}'")
        self.assertIn("<code class=\"inline\">TODO: a &lt;b&gt;</code>", checks.problem_html("todo", "TODO: a <b>"))
        self.assertEqual(checks.problem_md("black", "a | b"), "a \\| b")


if __name__ == "__main__":
    unittest.main()
