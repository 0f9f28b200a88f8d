#!/usr/bin/env python3
"""Unit tests of writeup/generator/page.py and page_items.py: from recipes
and finished (made-up) renders, the HTML page, the Markdown page and the
manifest: figures with their images, commands and times; a failed figure; a
flagged one, at the figure and in the list at the head; a table's numbers,
ratios, marks and conditions; the render-times table; number formats."""

import json
import os
import shutil
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import SCENES, import_generator  # noqa: E402

import_generator()
from generator import page, page_items  # noqa: E402
from generator.recipes import Recipes  # noqa: E402
from generator.scheduler import make_jobs  # noqa: E402

RECIPE = """
[settings]
title = "Page <test>"
scenes_dir = "{scenes}"
size = [40, 30]

[[section]]
id = "sec"
title = "Section"
text = "Uses `-m 2` & more."

[[section.grid]]
id = "g"
title = "Grid"
scene = "CBempty.dae"
args = "--part 3"
cells = [
  {{ label = "ok" }},
  {{ label = "also ok", name = "same" }},
  {{ label = "failed", args = "-l 2" }},
  {{ label = "flagged", args = "-l 3" }},
]

[[section.table]]
id = "t"
title = "Table"
scenes = ["CBempty.dae", "cow.dae"]
threads = 1
exclusive = true
variants = [ {{ label = "A", args = "--part 1" }}, {{ label = "B", args = "--part 2" }} ]
columns = [
  {{ title = "tests per ray", field = "tests_per_ray", variant = "A" }},
  {{ title = "speed-up", ratio = ["render_seconds", "A", "B"] }},
]
"""

SUMMARY = {"binary": "build/bin/pathtracer", "binary_sha256": "ab" * 32, "recipes": "figures.toml",
           "quick": False, "date": "2026-01-01 00:00", "renders": 8, "distinct_renders": 7, "rendered": 5,
           "cached": 2, "failed": 1, "flagged": 2, "wall_seconds": 75.0, "thread_budget": 2,
           "wall_thread_seconds": 150.0, "cpu_seconds": 140.0, "idle_estimate_seconds": 80.0}
TODO = "TODO: implement Part 3: x (y.cpp)"


def finished(job, status, render_seconds=0.25, threads=2, todo=(), black=False, error=None, stats=None):
    job.status, job.error = status, error
    job.stats = None if status == "failed" else {"render_seconds": render_seconds, "tests_per_ray": 12.5,
                                                  "max_radiance": 0.0 if black else 1.5, **(stats or {})}
    job.meta = {"argv": ["build/bin/pathtracer", "--part", "3", "-r", "40", "30", "-t", str(threads),
                         "--stats-json", "render.json", "-f", "render.png", "scenes/CBempty.dae"],
                "threads": threads, "wall_seconds": 1.5, "cpu_seconds": 2.5}
    job.checks = None if status == "failed" else {"todo": list(todo), "max_radiance": job.stats["max_radiance"],
                                                   "black": black, "image_error": None}


class PageTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="writeup-page-")
        self.addCleanup(shutil.rmtree, self.tmp, True)
        path = os.path.join(self.tmp, "figures.toml")
        with open(path, "w") as f:
            f.write(RECIPE.format(scenes=SCENES))
        self.recipes = Recipes(path, False)
        # "ok" and "also ok" have the same command: one render, two figures.
        self.jobs = make_jobs(self.recipes.renders, lambda r: str(r.flags) if r.grid == "g" else r.name)
        self.assertEqual(len(self.jobs), 7)
        fig = {f"{r.grid}/{r.name}": r for r in self.recipes.renders}
        finished(fig["g/ok"].job, "cached")
        finished(fig["g/failed"].job, "failed", error="pathtracer exited with status 1: bad <scene>")
        finished(fig["g/flagged"].job, "ok", todo=[TODO], black=True)
        finished(fig["t/cbempty_a"].job, "ok", render_seconds=2.0, threads=1)
        finished(fig["t/cbempty_b"].job, "ok", render_seconds=0.5, threads=1, todo=[TODO])
        finished(fig["t/cow_a"].job, "failed", threads=1, error="killed")
        finished(fig["t/cow_b"].job, "ok", render_seconds=0.001, threads=1, stats={"tests_per_ray": 3})
        self.page = page.Page(self.recipes, self.jobs, SUMMARY, "/x/build/bin/pathtracer").build()
        self.html, self.md = "".join(self.page.h), "".join(self.page.md)

    def test_figures_in_the_manifest(self):
        figs = {f["name"]: f for f in self.page.figures}
        self.assertEqual(list(figs), ["ok", "same", "failed", "flagged"])
        ok = figs["ok"]
        self.assertEqual((ok["status"], ok["cached"], ok["image"], ok["rate_image"], ok["max_radiance"]),
                         ("cached", True, "img/g/ok.png", None, 1.5))
        # A shared render shows each figure's own output names.
        self.assertTrue(ok["command"].endswith("--stats-json ok.json -f ok.png scenes/CBempty.dae"))
        self.assertTrue(figs["same"]["command"].endswith("--stats-json same.json -f same.png scenes/CBempty.dae"))
        self.assertEqual((figs["failed"]["image"], figs["failed"]["error"]),
                         (None, "pathtracer exited with status 1: bad <scene>"))
        self.assertEqual(figs["flagged"]["flags"],
                         [{"kind": "todo", "text": TODO},
                          {"kind": "black", "text": "the image is all black (every pixel 0)"}])
        self.assertEqual(figs["ok"]["flags"], [])

    def test_grid_html_and_markdown(self):
        h, md = self.html, self.md
        self.assertIn('<figure data-status="ok"><a href="img/g/ok.png"><img src="img/g/ok.png" alt="ok"></a>', h)
        self.assertIn('<span class="time">0.250 s, 2 threads</span>', h)
        self.assertIn('<figure class="failed" data-status="failed"><div class="placeholder">render failed:<br>'
                      'pathtracer exited with status 1: bad &lt;scene&gt;</div>', h)
        self.assertIn('<figure class="flagged" data-status="ok" data-flagged="todo black">', h)
        self.assertIn(f'<li>the renderer printed <code class="inline">{TODO}</code></li>', h)
        self.assertIn("| ![ok](img/g/ok.png)<br>**ok** (0.250 s, 2 threads)<br>`", md)
        self.assertIn("**failed**<br>FAILED: pathtracer exited with status 1: bad <scene><br>`", md)
        self.assertIn(f"**⚠ Check this figure:** the renderer printed `{TODO}`; the image is all black", md)
        self.assertIn("|---|---|---|---|\n", md)          # four columns

    def test_head_of_the_page(self):
        h, md = self.html, self.md
        self.assertTrue(h.startswith("<!DOCTYPE html>"))
        self.assertIn("<title>Page &lt;test&gt;</title>", h)
        self.assertIn("<p>Uses <code class=\"inline\">-m 2</code> &amp; more.</p>", h)
        self.assertIn('<div class="errors"><b>Failed renders</b><ul>\n<li><a href="#g">g/failed</a>', h)
        self.assertIn('<div class="warnings" id="flagged"><b>Figures to check (2)</b>', h)
        self.assertIn('<li><a href="#t">t/cbempty_b</a>: the renderer printed', h)
        self.assertIn("**Figures to check (2):**", md)
        self.assertIn(f"- ⚠ g/flagged: the renderer printed `{TODO}`; the image is all black (every pixel 0)\n", md)
        self.assertIn("- t/cow_a: killed\n", md)
        self.assertIn("All renders together took 2m30s of wall time × threads and 2m20s of CPU time: from "
                      "scratch, on 2 otherwise idle core(s), the page would take about 1m20s.", md)

    def test_table(self):
        t = self.page.tables[0]
        self.assertEqual(t["columns"], ["scene", "tests per ray", "speed-up"])
        self.assertEqual(t["rows"], [["CBempty.dae", "12.5", "4.0×"], ["cow.dae", "failed", "failed"]])
        self.assertEqual(t["numeric"], [[False, True, True], [False, False, False]])
        # The cell reading the flagged render (B of CBempty) is marked.
        self.assertIn('<tr><td class="">CBempty.dae</td><td class="num">12.5</td>'
                      '<td class="num flagged">4.0×</td></tr>', self.html)
        self.assertIn("| CBempty.dae | 12.5 | 4.0× ⚠ |", self.md)
        self.assertIn("Rendered at 40 × 30, on 1 thread each, each render alone (no other render of the "
                      "generator running beside it).", self.md)
        self.assertIn("- render failed: cow.dae, cow.dae, A: killed\n", self.md)
        self.assertIn(f"- ⚠ Check CBempty.dae, B: the renderer printed `{TODO}`\n", self.md)
        self.assertIn("<details><summary>The 4 commands</summary>", self.html)
        # A ratio above 100 drops the decimals; a missing field is a dash.
        fig = {f"{r.grid}/{r.name}": r for r in self.recipes.renders}
        finished(fig["t/cow_a"].job, "ok", render_seconds=2.0, threads=1)
        del fig["t/cow_a"].job.stats["tests_per_ray"]
        rows = page_items.table_cells(self.recipes.sections[0]["items"][1])
        self.assertEqual(rows[1], [("cow.dae", False), ("–", False), ("2,000×", True)])

    def test_render_times(self):
        h, md = self.html, self.md
        self.assertIn("| g/ok | ok | 0.250 | 1.500 | 2.500 | 2 | cached |", md)
        self.assertIn("| g/same | ok | 0.250 | 1.500 | 2.500 | 2 | cached |", md)
        self.assertIn("| g/failed | failed | – | 1.500 | 2.500 | 2 | failed |", md)
        self.assertIn("| g/flagged | check | 0.250 | 1.500 | 2.500 | 2 | this run |", md)
        self.assertIn('<td class="flagged">check</td>', h)
        # Each distinct render counted once (ok and same share one), a failed one not at all.
        self.assertIn("| Grid | 4 | 6s | 5s |", md)
        self.assertIn("| **total** | 8 | 2m30s | 2m20s |", md)
        self.assertTrue(h.endswith("</table>\n</section>\n</body>\n</html>\n"))

    def test_written_files(self):
        out = os.path.join(self.tmp, "out")
        os.makedirs(out)
        page.write_page(out, self.recipes, self.jobs, SUMMARY, "/x/build/bin/pathtracer")
        self.assertEqual(sorted(os.listdir(out)), ["index.html", "index.md", "manifest.json"])
        with open(os.path.join(out, "manifest.json")) as f:
            m = json.load(f)
        self.assertEqual(m["summary"], SUMMARY)
        self.assertEqual(m["figures"], json.loads(json.dumps(self.page.figures)))
        with open(os.path.join(out, "index.md"), encoding="utf-8") as f:
            self.assertEqual(f.read(), self.md)

    def test_number_formats(self):
        f = page_items.fmt_value
        self.assertEqual([f("rays", 1234567), f("render_seconds", 0.1234), f("render_seconds", 12.34),
                          f("x", 1234.5), f("x", 12.34), f("x", 0.5), f("x", 0.01234), f("x", None), f("x", "<a>")],
                         ["1,234,567", "0.123", "12.3", "1,234", "12.3", "0.50", "0.0123", "–", "&lt;a&gt;"])


if __name__ == "__main__":
    unittest.main()
