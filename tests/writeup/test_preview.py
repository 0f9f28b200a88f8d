#!/usr/bin/env python3
"""Unit tests of writeup/generator/preview.py: --quick's previews, the PFM a
render writes shrunk by a whole factor (block means), mapped to 8 bits by
the renderer's curve and written as a PNG; a preview that is one flat
colour is found; a bad PFM is an error naming the file."""

import math
import os
import struct
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True
from support import import_generator  # noqa: E402
from test_bvh_figures import read_png  # noqa: E402

import_generator()
from generator import preview  # noqa: E402


def write_pfm(path, width, height, pixel):
    """A PFM whose pixel (x, y), y from the top, is pixel(x, y) (three
    floats); rows stored from the bottom, little-endian, as the renderer's."""
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1\n".encode())
        for y in reversed(range(height)):
            for x in range(width):
                f.write(struct.pack("<3f", *pixel(x, y)))


def course_byte(L):
    """common/image_io.cpp's radiance_to_byte, written again."""
    v = math.sqrt(2.0) * L
    if not v > 0:
        return 0
    g = v ** (1 / 2.2)
    return 255 if g >= 1 else math.floor(255 * g)


class PreviewTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(prefix="writeup-preview-")
        self.addCleanup(self.tmp.cleanup)
        self.pfm = os.path.join(self.tmp.name, "render.pfm")
        self.png = os.path.join(self.tmp.name, "render.png")

    def test_shrink_averages_blocks_top_row_first(self):
        # 5 x 4, shrunk by 2: 2 x 2 (the last column dropped); pixel values
        # say where they are, so each block's mean is known.
        write_pfm(self.pfm, 5, 4, lambda x, y: (x, y, 10 * x + y))
        w, h, px = preview.read_pfm(self.pfm)
        self.assertEqual((w, h, len(px)), (5, 4, 60))
        w2, h2, rows = preview.shrink(w, h, px, 2)
        self.assertEqual((w2, h2), (2, 2))
        # Block (i, j) covers x = 2i, 2i + 1 and y = 2j, 2j + 1 (from the top).
        for j in range(2):
            for i in range(2):
                mx, my = 2 * i + 0.5, 2 * j + 0.5
                self.assertEqual(rows[j][3 * i:3 * i + 3], [mx, my, 10 * mx + my])
        self.assertEqual(preview.shrink(w, h, px, 1)[2][0][:6], [0, 0, 0, 1, 0, 10])

    def test_the_renderers_curve(self):
        for L in (0.0, -1.0, float("nan"), 1e-6, 0.01, 0.1, 0.3, 0.5, 0.7, 1 / math.sqrt(2), 3.0, float("inf")):
            self.assertEqual(preview.radiance_to_byte(L), 0 if L != L else course_byte(L), L)

    def test_make_preview_writes_the_png_and_finds_a_flat_one(self):
        write_pfm(self.pfm, 8, 6, lambda x, y: (0.5, 0.25, 0.0) if x < 4 else (0.0, 0.0, 0.1))
        info = preview.make_preview(self.pfm, self.png, 2)
        self.assertEqual((info["width"], info["height"], info["flat"]), (4, 3, False))
        w, h, rows = read_png(self.png)
        self.assertEqual((w, h), (4, 3))
        left = bytes(course_byte(v) for v in (0.5, 0.25, 0.0))
        right = bytes(course_byte(v) for v in (0.0, 0.0, 0.1))
        for row in rows:
            self.assertEqual(bytes(row), left * 2 + right * 2)
        # One colour everywhere (black, or a stub's single colour): flat.
        write_pfm(self.pfm, 8, 6, lambda x, y: (0.0, 0.0, 0.0))
        self.assertEqual(preview.make_preview(self.pfm, self.png, 4),
                         {"width": 2, "height": 1, "flat": True, "color": [0, 0, 0]})
        write_pfm(self.pfm, 8, 6, lambda x, y: (0.2, 0.2, 0.2))
        info = preview.make_preview(self.pfm, self.png, 2)
        self.assertEqual((info["flat"], info["color"]), (True, [course_byte(0.2)] * 3))
        # A factor larger than the image leaves one pixel.
        self.assertEqual(preview.make_preview(self.pfm, self.png, 50)["width"], 1)

    def test_bad_pfm_is_an_error_naming_the_file(self):
        for data in (b"P6\n2 2\n255\n", b"PF\n2 x\n-1\n", b"PF\n2 2\n-1\n" + b"\0" * 20):
            with open(self.pfm, "wb") as f:
                f.write(data)
            with self.assertRaises(ValueError) as e:
                preview.make_preview(self.pfm, self.png, 2)
            self.assertIn(self.pfm, str(e.exception))
        self.assertFalse(os.path.exists(self.png))


if __name__ == "__main__":
    unittest.main()
