#!/usr/bin/env python3
"""Unit tests of writeup/generator/recipes.py and flags.py: a recipe file
parsed and expanded into renders (flags merged, names, sizes, seeds,
expect_black, the --quick caps, --only), and bad recipes refused with the
file and the recipe named."""

import os
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import SCENES, import_generator  # noqa: E402

import_generator()
from generator import flags, recipes  # noqa: E402
from generator.base import InputError  # noqa: E402

RECIPE = """
[settings]
title = "unit"
scenes_dir = "{scenes}"
size = [40, 30]
seed = 7
quick_size = [16, 12]
quick_max_samples = 4
quick_max_light_samples = 2

[[section]]
id = "s1"
title = "One"
text = "Some `code`."

[[section.grid]]
id = "sweep"
scene = "CBempty.dae"
args = "--part 4 -s 16 -l 8 -m 2"
vary = {{ flag = "-a", values = [[64, 0.05], [2, 0.1]] }}

[[section.grid]]
id = "cells"
scene = "CBempty.dae"
args = "--part 3 -m 1 -s 1"
expect_black = "quick"
cells = [
  {{ label = "CBbunny.dae (hemisphere)", scene = "CBbunny.dae", args = "-H -s 8" }},
  {{ label = "same", size = [20, 10], seed = 9, expect_black = false }},
  {{ label = "same", name = "custom name", args = "-m 3", expect_black = true }},
  {{ label = "few samples", args = "-s 8", quick_max_samples = 6 }},
  {{ label = "boxes", args = "--part 2 --bvh-boxes 3" }},
]

[[section]]
id = "s2"

[[section.table]]
id = "tab"
scenes = ["CBempty.dae", "cow.dae"]
args = "-s 1"
threads = 1
exclusive = true
variants = [ {{ label = "no BVH", args = "--part 1" }}, {{ label = "BVH", args = "--part 2" }} ]
columns = [
  {{ title = "render s", field = "render_seconds", variant = "no BVH" }},
  {{ title = "speed-up", ratio = ["render_seconds", "no BVH", "BVH"] }},
]
"""


TMP = tempfile.TemporaryDirectory(prefix="writeup-recipes-")


def tearDownModule():
    TMP.cleanup()


class RecipeFile:
    """A recipe file written into the tests' temporary folder."""

    count = 0

    def __init__(self, text):
        RecipeFile.count += 1
        self.path = os.path.join(TMP.name, f"figures{RecipeFile.count}.toml")
        with open(self.path, "w") as f:
            f.write(text)

    def load(self, quick=False):
        return recipes.Recipes(self.path, quick)


def by_name(rs):
    return {f"{r.grid}/{r.name}": r for r in rs.renders}


class FlagsTest(unittest.TestCase):
    def test_parse_and_merge(self):
        f = flags.parse_flags("-s 4 -a 8 0.1 -H --part 3", "w")
        self.assertEqual(f, [("-s", ["4"]), ("-a", ["8", "0.1"]), ("-H", []), ("--part", ["3"])])
        merged = flags.merge_flags(f, [("-s", ["16"]), ("-m", ["2"])])
        # A flag in both keeps its place with the new values; a new one goes last.
        self.assertEqual(flags.flat(merged), ["-s", "16", "-a", "8", "0.1", "-H", "--part", "3", "-m", "2"])
        self.assertEqual(flags.get_flag(merged, "-m"), ["2"])
        self.assertIsNone(flags.get_flag(merged, "-l"))

    def test_bad_flags(self):
        for text, words in (("--frobnicate", ["unknown pathtracer flag", "--frobnicate"]),
                            ("-s", ["-s needs 1 value"]), ("-a 8 -H", ["-a needs 2 value"]),
                            ("-t 4", ["generator sets -t", "'threads'"]), ("-r 3 4", ["sets -r", "'size'"]),
                            ("--stats-json x.json", ["sets --stats-json itself"]), ("-s '4", ["cannot split"])):
            with self.assertRaises(InputError) as e:
                flags.parse_flags(text, "where")
            for w in words:
                self.assertIn(w, str(e.exception))
            self.assertTrue(str(e.exception).startswith("where: "))


class RecipesTest(unittest.TestCase):
    def setUp(self):
        self.file = RecipeFile(RECIPE.format(scenes=SCENES))

    def test_sections_and_items(self):
        rs = self.file.load()
        self.assertEqual(rs.title, "unit")
        self.assertEqual([s["id"] for s in rs.sections], ["s1", "s2"])
        self.assertEqual(rs.sections[1]["title"], "s2")  # the id when there is no title
        self.assertEqual([it["id"] for it in rs.sections[0]["items"]], ["sweep", "cells"])
        self.assertEqual(len(rs.renders), 2 + 5 + 4)
        table = rs.sections[1]["items"][0]
        self.assertEqual(table["variants"], ["no BVH", "BVH"])
        self.assertEqual([row["scene"] for row in table["rows"]], ["CBempty.dae", "cow.dae"])

    def test_vary_expands_one_render_per_value(self):
        rs = by_name(self.file.load())
        r = rs["sweep/a_64_0_05"]
        self.assertEqual(r.label, "-a 64 0.05")
        self.assertEqual(flags.flat(r.flags), ["--part", "4", "-s", "16", "-l", "8", "-m", "2", "-a", "64", "0.05"])
        self.assertEqual((r.size, r.seed), ((40, 30), 7))
        self.assertIn("sweep/a_2_0_1", rs)

    def test_cells_override_the_grid(self):
        rs = by_name(self.file.load())
        self.assertEqual(sorted(k for k in rs if k.startswith("cells/")),
                         ["cells/boxes", "cells/cbbunny", "cells/custom_name", "cells/few_samples", "cells/same"])
        bunny = rs["cells/cbbunny"]
        self.assertEqual(flags.flat(bunny.flags), ["--part", "3", "-m", "1", "-s", "8", "-H"])
        self.assertEqual(os.path.basename(bunny.scene), "CBbunny.dae")
        same = rs["cells/same"]
        self.assertEqual((same.size, same.seed), ((20, 10), 9))
        self.assertEqual(os.path.basename(same.scene), "CBempty.dae")
        self.assertEqual(flags.get_flag(rs["cells/custom_name"].flags, "-m"), ["3"])

    def test_a_repeated_name_gets_a_number(self):
        text = RECIPE.format(scenes=SCENES).replace('name = "custom name", ', "")
        rs = by_name(RecipeFile(text).load())
        self.assertIn("cells/same", rs)
        self.assertIn("cells/same_2", rs)

    def test_expect_black(self):
        full, quick = by_name(self.file.load()), by_name(self.file.load(quick=True))
        # The grid says "quick": black only in --quick renders; cells override it.
        self.assertEqual([full[k].expect_black for k in ("cells/cbbunny", "cells/same", "cells/custom_name")],
                         [False, False, True])
        self.assertEqual([quick[k].expect_black for k in ("cells/cbbunny", "cells/same", "cells/custom_name")],
                         [True, False, True])
        self.assertFalse(full["sweep/a_64_0_05"].expect_black)

    def test_quick_caps(self):
        rs = by_name(self.file.load(quick=True))
        r = rs["sweep/a_64_0_05"]
        # An image keeps its size (the whole view) and is shrunk to at most
        # quick_size afterwards: 40 x 30 by 3 (ceil(40 / 16), ceil(30 / 12)).
        self.assertEqual((r.size, r.preview), ((40, 30), 3))
        self.assertEqual(flags.get_flag(r.flags, "-s"), ["4"])
        self.assertEqual(flags.get_flag(r.flags, "-l"), ["2"])
        self.assertEqual(flags.get_flag(r.flags, "-a"), ["1", "0.05"])   # batch at most a quarter of -s
        self.assertEqual(flags.get_flag(rs["sweep/a_2_0_1"].flags, "-a"), ["1", "0.1"])
        self.assertEqual((rs["cells/same"].size, rs["cells/same"].preview), ((20, 10), 2))
        self.assertEqual(flags.get_flag(rs["cells/cbbunny"].flags, "-s"), ["4"])
        self.assertEqual(flags.get_flag(rs["cells/few_samples"].flags, "-s"), ["6"])  # the cell's own cap
        self.assertEqual(rs["cells/boxes"].preview, 1)  # drawn over the PNG: not shrunk
        # A table's renders, whose numbers alone are shown, are quick_size.
        self.assertEqual((rs["tab/cow_bvh"].size, rs["tab/cow_bvh"].preview), ((16, 12), 1))
        full = by_name(self.file.load())
        self.assertEqual({r.preview for r in full.values()}, {1})
        self.assertEqual(flags.get_flag(full["cells/few_samples"].flags, "-s"), ["8"])
        # Timing renders do not run alone in --quick, and remember that they would have.
        t = rs["tab/cbempty_no_bvh"]
        self.assertEqual((t.exclusive, t.quick_exclusive, t.threads), (False, True, 1))
        full = by_name(self.file.load())["tab/cbempty_no_bvh"]
        self.assertEqual((full.exclusive, full.quick_exclusive), (True, False))

    def test_table_renders(self):
        rs = by_name(self.file.load())
        self.assertEqual(sorted(k for k in rs if k.startswith("tab/")),
                         ["tab/cbempty_bvh", "tab/cbempty_no_bvh", "tab/cow_bvh", "tab/cow_no_bvh"])
        r = rs["tab/cow_bvh"]
        self.assertEqual(r.label, "cow.dae, BVH")
        self.assertEqual(flags.flat(r.flags), ["-s", "1", "--part", "2"])

    def test_only(self):
        rs = self.file.load()
        rs.select("ta*, sweep")
        self.assertEqual([[it["id"] for it in s["items"]] for s in rs.sections], [["sweep"], ["tab"]])
        self.assertEqual({r.grid for r in rs.renders}, {"sweep", "tab"})
        rs = self.file.load()
        rs.select("tab")
        self.assertEqual([s["id"] for s in rs.sections], ["s2"])
        with self.assertRaisesRegex(InputError, "--only: no grid or table matches 'nope'"):
            self.file.load().select("tab,nope")


class BadRecipesTest(unittest.TestCase):
    def refused(self, old, new, *words, count=1):
        text = RECIPE.format(scenes=SCENES)
        self.assertIn(old, text)
        file = RecipeFile(text.replace(old, new, count))
        with self.assertRaises(InputError) as e:
            file.load()
        msg = str(e.exception)
        self.assertTrue(msg.startswith(file.path + ": "), msg)   # one line naming the file first
        for w in words:
            self.assertIn(w, msg)

    def test_each_bad_field_is_named(self):
        self.refused('id = "sweep"', 'id = "sweep"\ncolour = 3', "grid 'sweep'", "unknown field 'colour'")
        self.refused("seed = 7", 'seed = "7"', "[settings]", "'seed' must be an integer")
        self.refused("size = [40, 30]", "size = [40]", "[settings]", "'size'")
        self.refused('label = "same", size = [20, 10]', 'label = "same", size = [20, 0]', "cell 'same'", "size")
        self.refused('args = "-H -s 8"', 'args = "-H -t 8"', "cell 'CBbunny.dae (hemisphere)'", "-t")
        self.refused('expect_black = "quick"', 'expect_black = "yes"', "grid 'cells'", "expect_black")
        self.refused('scene = "CBbunny.dae"', 'scene = "nope.dae"', "cell 'CBbunny.dae (hemisphere)'", "nope.dae")
        self.refused('id = "cells"', 'id = "sweep"', "grid id 'sweep' is used twice")
        self.refused('id = "cells"', 'id = "a b"', "may only hold letters")
        self.refused('vary = {', 'cells = []\nvary = {', "grid 'sweep'", "either 'vary' or 'cells'")
        self.refused("threads = 1", "threads = 0", "table 'tab'", "'threads'")
        self.refused("quick_max_samples = 6", "quick_max_samples = 0", "cell 'few samples'", "'quick_max_samples'")
        self.refused("quick_max_samples = 6", 'quick_max_samples = "6"', "cell 'few samples'", "'quick_max_samples'")
        self.refused('ratio = ["render_seconds", "no BVH", "BVH"]', 'ratio = ["render_seconds", "no BVH", "GPU"]',
                     "table 'tab', column 2", "'ratio'")
        self.refused('variant = "no BVH"', 'variant = "GPU"', "unknown variant 'GPU'")
        self.refused('id = "sweep"\n', "", "section 's1'", "a grid has no 'id'")
        self.refused('title = "unit"', 'title = "unit\n', "not valid TOML")
        with self.assertRaisesRegex(InputError, r"no \[\[section\]\]"):
            RecipeFile('[settings]\ntitle = "x"\n').load()
        with self.assertRaisesRegex(InputError, "recipe file not found"):
            recipes.Recipes("/nonexistent/figures.toml", False)


if __name__ == "__main__":
    unittest.main()
