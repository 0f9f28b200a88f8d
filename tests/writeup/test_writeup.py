#!/usr/bin/env python3
"""Tests of the write-up figure generator (writeup/make_figures.py).

    test_writeup.py quick   --pathtracer EXE --artifacts DIR
    test_writeup.py browser --artifacts DIR
    test_writeup.py cache   --pathtracer EXE
    test_writeup.py errors  --pathtracer EXE

quick:   a --quick run of the real recipes into DIR/quick: every figure
         rendered, every image the page references exists, every table
         cell a number.
browser: that page in headless Chromium: it loads, every image loads, no
         errors; screenshots DIR/page.png (1280 x 2000) and DIR/page_full.png.
cache:   a second run renders nothing; changing one recipe re-renders only
         that render; another binary re-renders everything.
errors:  bad recipes and a missing binary give one line naming the recipe or
         file and exit 2; a failed render is a failed figure on the page and
         exit 1.
flags:   with a fake pathtracer that prints a TODO line for some renders and
         writes all-black images for others, those figures are flagged in the
         HTML and the Markdown page (at the figure and in the list at the
         head) and the run exits 3, again from the cache; the other figures,
         one of them black but for one pixel, are not flagged.
reference: with the real pathtracer, a lit render is not flagged, a black
         one is (the PNG as the renderer writes it), and not where the recipe
         says expect_black.
png:     the black check on PNGs written here in every layout (colour types,
         bit depths, filters, interlacing): black is black, one pixel of the
         smallest value is not.
text:    the recipes' prose states no fixed render times or speed-ups.
"""

import argparse
import html.parser
import importlib.util
import json
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import tomllib
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GENERATOR = os.path.join(ROOT, "writeup", "make_figures.py")
CHECKER = os.path.join(ROOT, "writeup", "check_page.py")
RECIPES = os.path.join(ROOT, "writeup", "figures.toml")

failures = []


def generator_module():
    """make_figures.py as a module (for its PNG check)."""
    sys.dont_write_bytecode = True  # nothing written into the source tree
    spec = importlib.util.spec_from_file_location("make_figures", GENERATOR)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}", flush=True)
    return cond


def run(args, **kw):
    t0 = time.monotonic()
    r = subprocess.run([sys.executable] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    r.seconds = time.monotonic() - t0
    return r


class PageParser(html.parser.HTMLParser):
    """The page's <img> sources and its tables (class "stats") as rows of cells."""

    def __init__(self):
        super().__init__()
        self.images = []
        self.tables = {}
        self._table = None
        self._cell = None
        self._row = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src"))
        elif tag == "table" and "stats" in (a.get("class") or ""):
            self._table = self.tables.setdefault(a.get("id"), [])
        elif tag == "tr" and self._table is not None:
            self._row = []
            self._table.append(self._row)
        elif tag in ("td", "th") and self._row is not None:
            self._cell = [tag, ""]
            self._row.append(self._cell)

    def handle_endtag(self, tag):
        if tag == "table":
            self._table = self._row = None
        elif tag in ("td", "th"):
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[1] += data


def expected_items(path):
    """(id, "grid" or "table", number of renders) for every grid and table of a recipe file."""
    with open(path, "rb") as f:
        data = tomllib.load(f)
    out = []
    for sec in data["section"]:
        for g in sec.get("grid", []):
            out.append((g["id"], "grid", len(g["vary"]["values"]) if "vary" in g else len(g["cells"])))
        for t in sec.get("table", []):
            out.append((t["id"], "table", len(t["scenes"]) * len(t.get("variants", [0]))))
    return out


NUMBER = re.compile(r"^-?[0-9][0-9,]*(\.[0-9]+)?×?$")


def test_quick(a):
    out = os.path.join(a.artifacts, "quick")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(a.artifacts, exist_ok=True)
    r = run([GENERATOR, "--quick", "--pathtracer", a.pathtracer, "--out", out])
    sys.stdout.write(r.stdout)
    sys.stdout.write(r.stderr)
    print(f"--quick run: {r.seconds:.1f} s")
    if not check(r.returncode == 0, f"--quick exits 0 (got {r.returncode})"):
        return
    manifest = json.load(open(os.path.join(out, "manifest.json")))
    figures = manifest["figures"]
    items = expected_items(RECIPES)
    for gid, kind, n in items:
        if kind != "grid":
            continue
        got = [f for f in figures if f["grid"] == gid]
        check(len(got) == n, f"grid {gid}: {n} figures on the page (got {len(got)})")
    for f in figures:
        check(f["status"] in ("ok", "cached"), f"{f['grid']}/{f['name']} rendered (status {f['status']})")
        check(f["image"] and os.path.isfile(os.path.join(out, f["image"])), f"{f['grid']}/{f['name']}: image exists")
        if f.get("rate"):
            check(os.path.isfile(os.path.join(out, f["rate_image"])), f"{f['grid']}/{f['name']}: rate image exists")
        check(f["command"].split()[0].endswith("pathtracer") and "--seed" in f["command"],
              f"{f['grid']}/{f['name']}: the command is shown")
    check(manifest["summary"]["failed"] == 0, "no render failed")

    p = PageParser()
    p.feed(open(os.path.join(out, "index.html"), encoding="utf-8").read())
    check(len(p.images) >= len(figures), f"the page shows every figure ({len(p.images)} images, {len(figures)} figures)")
    for src in p.images:
        check(src and os.path.isfile(os.path.join(out, src)), f"image referenced by the page exists: {src}")
    md = open(os.path.join(out, "index.md"), encoding="utf-8").read()
    for src in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md):
        check(os.path.isfile(os.path.join(out, src)), f"image referenced by index.md exists: {src}")

    tables = {k: v for k, v in p.tables.items() if k and k.startswith("table-")}
    expected_tables = {f"table-{gid}" for gid, kind, _ in items if kind == "table"}
    check(set(tables) == expected_tables, f"the page has the tables {sorted(expected_tables)} (got {sorted(tables)})")
    for tid, rows in tables.items():
        body = [row for row in rows if row and row[0][0] == "td"]
        check(len(body) > 0, f"{tid} has rows")
        for row in body:
            for tag, text in row[1:]:
                check(NUMBER.match(text.strip()), f"{tid}, {row[0][1]}: cell '{text}' is a number")
    times = p.tables.get("render-times", [])
    check(len([r for r in times if r and r[0][0] == "td"]) == sum(n for _, _, n in items),
          "the render-time table lists every render")

    # The reference build: no figure flagged; a figure the recipes expect to be
    # black really is (an expect_black that is not needed would hide a fault).
    check(manifest["summary"]["flagged"] == 0, f"no figure flagged (got {manifest['summary']['flagged']})")
    mf = generator_module()
    for f in figures:
        check(f["flags"] == [], f"{f['grid']}/{f['name']} is not flagged (got {f['flags']})")
        if f["expect_black"]:
            check(mf.png_is_black(os.path.join(out, f["image"])),
                  f"{f['grid']}/{f['name']} is expected to be black and is")
    check("Figures to check" not in open(os.path.join(out, "index.html"), encoding="utf-8").read()
          and "Figures to check" not in md, "no list of figures to check on the page")


def test_browser(a):
    page = os.path.join(a.artifacts, "quick", "index.html")
    shot = os.path.join(a.artifacts, "page.png")
    full = os.path.join(a.artifacts, "page_full.png")
    if not os.path.exists("/usr/bin/chromium") and not shutil.which("chromium"):
        check(False, "chromium is not installed: run scripts/setup.sh (as root) to install it")
        return
    r = run([CHECKER, page, "--screenshot", shot, "--full-screenshot", full])
    sys.stdout.write(r.stdout)
    sys.stdout.write(r.stderr)
    check(r.returncode == 0, f"the page loads in chromium with every image (exit {r.returncode})")
    check(os.path.isfile(shot) and os.path.getsize(shot) > 10000, f"screenshot kept: {shot}")


TINY = """
[settings]
title = "cache test"
scenes_dir = "{scenes}"
size = [32, 24]
seed = 3

[[section]]
id = "s"
title = "Section"

[[section.grid]]
id = "g"
title = "Grid"
scene = "CBspheres_lambertian.dae"
args = "--part 3 -m 1 -s 1"
vary = {{ flag = "-l", values = [1, 2] }}

[[section.grid]]
id = "h"
title = "Other"
cells = [ {{ label = "normals", scene = "CBempty.dae", args = "--part 2 {extra}" }} ]
"""


def summary(out):
    return json.load(open(os.path.join(out, "manifest.json")))["summary"]


def test_cache(a):
    tmp = tempfile.mkdtemp(prefix="writeup-cache-")
    try:
        recipes = os.path.join(tmp, "figures.toml")
        out = os.path.join(tmp, "out")
        scenes = os.path.join(ROOT, "scenes")

        def generate(extra="", binary=a.pathtracer):
            with open(recipes, "w") as f:
                f.write(TINY.format(scenes=scenes, extra=extra))
            r = run([GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", binary, "--no-progress"])
            check(r.returncode == 0, f"run exits 0 ({r.stderr.strip()})")
            return summary(out)

        s = generate()
        check((s["rendered"], s["cached"]) == (3, 0), f"first run renders all 3 (got {s['rendered']} rendered)")
        first = open(os.path.join(out, "img", "g", "l_2.png"), "rb").read()
        s = generate()
        check((s["rendered"], s["cached"]) == (0, 3), f"second run renders nothing ({s['rendered']} rendered)")
        check(open(os.path.join(out, "img", "g", "l_2.png"), "rb").read() == first, "the cached image is the same")
        s = generate(extra="-s 2")
        check((s["rendered"], s["cached"]) == (1, 2), f"one changed recipe re-renders one ({s['rendered']} rendered)")
        s = generate(extra="-s 2")
        check(s["rendered"] == 0, "and then nothing")
        # Another binary (same program, one more byte): everything again.
        other = os.path.join(tmp, "pathtracer-copy")
        shutil.copyfile(a.pathtracer, other)
        with open(other, "ab") as f:
            f.write(b"\0")
        os.chmod(other, 0o755)
        s = generate(extra="-s 2", binary=other)
        check((s["rendered"], s["cached"]) == (3, 0), f"another binary re-renders all 3 ({s['rendered']} rendered)")
        # --quick renders differ from the full ones; the dry run renders nothing.
        r = run([GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", other, "--dry-run"])
        check(r.returncode == 0 and r.stdout.count("cached") == 3, "--dry-run lists the 3 renders as cached")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


BAD = """
[settings]
scenes_dir = "{scenes}"
size = [16, 12]

[[section]]
id = "s"

[[section.grid]]
id = "bad_grid"
scene = "CBempty.dae"
args = "--part 2"
{extra}
cells = [ {{ label = "good" }}{cells} ]
"""


def test_errors(a):
    tmp = tempfile.mkdtemp(prefix="writeup-errors-")
    try:
        recipes = os.path.join(tmp, "figures.toml")
        out = os.path.join(tmp, "out")
        scenes = os.path.join(ROOT, "scenes")

        def generate(extra="", cells="", binary=a.pathtracer):
            with open(recipes, "w") as f:
                f.write(BAD.format(scenes=scenes, extra=extra, cells=cells))
            return run([GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", binary, "--no-progress"])

        def one_line_error(r, status, *words):
            lines = r.stderr.strip().splitlines()
            ok = (r.returncode == status and len(lines) == 1 and lines[0].startswith("make_figures.py: error:")
                  and all(w in lines[0] for w in words))
            check(ok, f"one-line error with {words}, exit {status} (got exit {r.returncode}: {r.stderr.strip()!r})")

        one_line_error(generate(extra="colour = 3"), 2, "figures.toml", "bad_grid", "unknown field 'colour'")
        one_line_error(generate(cells=', { label = "x", size = [1] }'), 2, "bad_grid", "cell 'x'", "size")
        one_line_error(generate(cells=', { label = "y", args = "--frobnicate" }'), 2, "cell 'y'", "--frobnicate")
        one_line_error(generate(cells=', { label = "z", args = "-f mine.png" }'), 2, "cell 'z'", "-f")
        one_line_error(generate(cells=', { label = "w", scene = "nope.dae" }'), 2, "cell 'w'", "nope.dae")
        one_line_error(generate(cells=', { label = "v", expect_black = "yes" }'), 2, "cell 'v'", "expect_black")
        one_line_error(generate(extra="args = ["), 2, "figures.toml", "TOML")
        one_line_error(generate(binary=os.path.join(tmp, "no-such-pathtracer")), 2, "no-such-pathtracer")

        # A render that fails: on the page as a failed figure, the others fine, exit 1.
        broken = os.path.join(tmp, "broken.dae")
        with open(broken, "w") as f:
            f.write("this is not a COLLADA file\n")
        r = generate(cells=f', {{ label = "broken", scene = "{broken}" }}')
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 1, f"a failed render exits 1 (got {r.returncode})")
        check(len(lines) == 1 and "bad_grid/broken" in lines[0] and "broken.dae" in lines[0],
              f"one line names the failed render and its error: {r.stderr.strip()!r}")
        m = json.load(open(os.path.join(out, "manifest.json")))
        st = {f["name"]: f for f in m["figures"]}
        check(st["good"]["status"] == "ok" and os.path.isfile(os.path.join(out, st["good"]["image"])),
              "the other figure still renders")
        check(st["broken"]["status"] == "failed" and "broken.dae" in (st["broken"]["error"] or ""),
              "the failed figure carries its error")
        page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
        check("render failed" in page and "data-status=\"failed\"" in page, "the page shows the failed figure")
        # A failed render is not cached: the next run tries it again.
        r = generate(cells=f', {{ label = "broken", scene = "{broken}" }}')
        check(r.returncode == 1 and summary(out)["rendered"] == 1, "a failed render is tried again")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


# ---------------------------------------------------------------------------
# Flagged figures: TODO lines and all-black images

# Adam7 passes (first column, first row, column step, row step), for the PNGs written here.
ADAM7 = ((0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2))
CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def png_filter(f, row, prev, step):
    """One scanline filtered with PNG filter type f."""
    out = bytearray(len(row))
    for i in range(len(row)):
        a = row[i - step] if i >= step else 0
        b = prev[i]
        c = prev[i - step] if i >= step else 0
        if f == 0:
            p = 0
        elif f == 1:
            p = a
        elif f == 2:
            p = b
        elif f == 3:
            p = (a + b) // 2
        else:
            q = a + b - c
            pa, pb, pc = abs(q - a), abs(q - b), abs(q - c)
            p = a if pa <= pb and pa <= pc else b if pb <= pc else c
        out[i] = (row[i] - p) & 255
    return out


def png_pack(pixels, depth):
    """A scanline's bytes from pixels (tuples of samples)."""
    if depth >= 8:
        return bytearray(b"".join(v.to_bytes(depth // 8, "big") for px in pixels for v in px))
    out = bytearray((len(pixels) * depth + 7) // 8)
    for i, (v,) in enumerate(pixels):
        out[(i * depth) >> 3] |= v << (8 - depth - (i * depth) % 8)
    return out


def png_bytes(pixels, colour, depth, interlace=0, palette=None, filters=(0, 1, 2, 3, 4)):
    """A PNG file of pixels (rows of tuples of samples); scanline k uses filters[k % len]."""
    height, width = len(pixels), len(pixels[0])
    step = max(1, CHANNELS[colour] * depth // 8)
    raw = bytearray()
    k = 0
    for x0, y0, dx, dy in (ADAM7 if interlace else ((0, 0, 1, 1),)):
        xs, ys = range(x0, width, dx), range(y0, height, dy)
        if not xs or not ys:
            continue
        prev = bytearray((len(xs) * CHANNELS[colour] * depth + 7) // 8)
        for y in ys:
            row = png_pack([pixels[y][x] for x in xs], depth)
            f = filters[k % len(filters)]
            k += 1
            raw.append(f)
            raw += png_filter(f, row, prev, step)
            prev = row
    chunks = [(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, interlace))]
    if palette is not None:
        chunks.append((b"PLTE", bytes(v for rgb in palette for v in rgb)))
    chunks += [(b"IDAT", zlib.compress(bytes(raw))), (b"IEND", b"")]
    return b"\x89PNG\r\n\x1a\n" + b"".join(struct.pack(">I", len(body)) + kind + body
                                           + struct.pack(">I", zlib.crc32(kind + body)) for kind, body in chunks)


def black_pixels(width, height, colour, depth):
    """Black pixels (opaque where there is alpha; palette index 1, which is black in PALETTE)."""
    top = (1 << depth) - 1
    px = {0: (0,), 2: (0, 0, 0), 3: (1,), 4: (0, top), 6: (0, 0, 0, top)}[colour]
    return [[px] * width for _ in range(height)]


# Index 0 is the dimmest colour there is, index 1 black, the rest bright and unused.
PALETTE = [(0, 0, 1), (0, 0, 0)] + [(255, 255, 255)] * 254


def write_black_png(path, width, height, dim_pixel=None):
    """An all-black RGB PNG or, with dim_pixel = (x, y), one black but for one
    green sample of 1 there (scanlines filtered with each filter type in turn)."""
    pixels = black_pixels(width, height, 2, 8)
    if dim_pixel is not None:
        pixels[dim_pixel[1]][dim_pixel[0]] = (0, 1, 0)
    data = png_bytes(pixels, 2, 8)
    with open(path, "wb") as f:
        f.write(data)


def test_png(a):
    mf = generator_module()
    rng = random.Random(184)
    tmp = tempfile.mkdtemp(prefix="writeup-png-")
    layouts = [(0, 1), (0, 2), (0, 4), (0, 8), (0, 16), (2, 8), (2, 16), (3, 1), (3, 2), (3, 4), (3, 8),
               (4, 8), (4, 16), (6, 8), (6, 16)]
    try:
        path = os.path.join(tmp, "x.png")
        n = 0
        for width, height in ((1, 1), (3, 2), (13, 11), (40, 9)):
            for colour, depth in layouts:
                for interlace in (0, 1):
                    palette = PALETTE[:1 << depth] if colour == 3 else None
                    pixels = black_pixels(width, height, colour, depth)
                    what = f"{width}x{height} colour type {colour}, {depth} bit, interlace {interlace}"
                    with open(path, "wb") as f:
                        f.write(png_bytes(pixels, colour, depth, interlace, palette))
                    check(mf.png_is_black(path) is True, f"{what}: black is black")
                    # One pixel of the smallest non-zero value in one colour channel.
                    x, y = rng.randrange(width), rng.randrange(height)
                    px = list(pixels[y][x])
                    if colour == 3:
                        px[0] = 0
                    else:
                        px[rng.randrange(3 if colour in (2, 6) else 1)] = 1
                    pixels[y][x] = tuple(px)
                    with open(path, "wb") as f:
                        f.write(png_bytes(pixels, colour, depth, interlace, palette))
                    check(mf.png_is_black(path) is False, f"{what}: one dim pixel at ({x}, {y}) is not black")
                    n += 2
        # Palette images whose random indices all name black entries (the odd ones are
        # not black): a scanline read wrong would land on a bright entry.
        for depth in (2, 4, 8):
            for interlace in (0, 1):
                palette = [(0, 0, 0) if i % 2 == 0 else (255, 255, 255) for i in range(1 << depth)]
                pixels = [[(2 * rng.randrange(1 << (depth - 1)),) for _ in range(29)] for _ in range(17)]
                with open(path, "wb") as f:
                    f.write(png_bytes(pixels, 3, depth, interlace, palette))
                check(mf.png_is_black(path) is True,
                      f"a {depth}-bit palette image of random black entries (interlace {interlace}) is black")
                n += 1
        # Alpha is not colour: a transparent pixel is as black as an opaque one, and
        # a non-zero alpha on black does not make it coloured.
        pixels = [[(0, 0, 0, rng.randrange(256)) for _ in range(7)] for _ in range(5)]
        with open(path, "wb") as f:
            f.write(png_bytes(pixels, 6, 8))
        check(mf.png_is_black(path) is True, "black with random alpha is black")
        for bad in (b"GIF89a not a png", png_bytes(black_pixels(9, 9, 2, 8), 2, 8)[:60]):
            with open(path, "wb") as f:
                f.write(bad)
            try:
                mf.png_is_black(path)
                check(False, f"an unreadable PNG raises ValueError ({bad[:8]!r})")
            except ValueError:
                pass
        print(f"{n + 3} PNGs checked")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


TODO_LINE = ("TODO: implement Part 3: estimate_direct_lighting_hemisphere "
             "(stages/part3_direct_lighting/direct_lighting.cpp)")

FAKE = """#!{python}
# A pathtracer for the write-up tests (tests/writeup/test_writeup.py, fake_pathtracer).
import sys
sys.dont_write_bytecode = True
sys.path.insert(0, {testdir!r})
import test_writeup
sys.exit(test_writeup.fake_pathtracer({real!r}, sys.argv[1:]))
"""


def fake_pathtracer(real, args):
    """Renders with the real pathtracer, except that
       -H             first prints a TODO line on stderr, as a starter-kit build does
                      the first time it reaches a function not written yet;
       --no-rr        then replaces the image with an all-black one of the same size;
       --direct-only  then replaces it with one black but for one pixel of value 1."""
    if "-H" in args:
        sys.stderr.write(TODO_LINE + "\n")
        sys.stderr.flush()
    rc = subprocess.call([real] + args)
    if rc != 0:
        return rc
    out = args[args.index("-f") + 1]
    i = args.index("-r")
    width, height = int(args[i + 1]), int(args[i + 2])
    if "--no-rr" in args:
        write_black_png(out, width, height)
    elif "--direct-only" in args:
        rng = random.Random(width * 1000 + height)
        write_black_png(out, width, height, dim_pixel=(rng.randrange(width), rng.randrange(height)))
    return 0


FLAGS = """
[settings]
title = "flag test"
scenes_dir = "{scenes}"
size = [24, 18]
seed = 5

[[section]]
id = "s"
title = "Section"

[[section.grid]]
id = "g"
title = "Grid"
scene = "CBspheres_lambertian.dae"
args = "--part 4 -s 1 -l 1 -m 2"
cells = [
  {{ label = "plain" }},
  {{ label = "todo", args = "-H" }},
  {{ label = "black", args = "--no-rr" }},
  {{ label = "dim", args = "--direct-only" }},
  {{ label = "black by design", name = "expected", args = "--no-rr -m 3", expect_black = true }},
]

[[section.table]]
id = "t"
title = "Table"
scene = "CBempty.dae"
args = "--part 3 -m 1 -s 1"
variants = [ {{ label = "light" }}, {{ label = "hemisphere", args = "-H" }} ]
columns = [
  {{ title = "render s, light", field = "render_seconds", variant = "light" }},
  {{ title = "render s, hemisphere", field = "render_seconds", variant = "hemisphere" }},
]
"""


class FlagParser(html.parser.HTMLParser):
    """Each <figure>'s attributes, image sources and text; the text and links of the
    list of figures to check (id "flagged"); the warnings under tables."""

    def __init__(self):
        super().__init__()
        self.figures = []
        self.head_text = ""
        self.head_links = []
        self.table_warnings = []
        self._figure = None
        self._head_depth = 0
        self._p = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "figure":
            self._figure = {"attrs": a, "images": [], "text": ""}
            self.figures.append(self._figure)
        elif tag == "img" and self._figure is not None:
            self._figure["images"].append(a.get("src"))
        if tag == "div" and (self._head_depth or a.get("id") == "flagged"):
            self._head_depth += 1
        if tag == "a" and self._head_depth:
            self.head_links.append(a.get("href"))
        if tag == "p" and "warning" in (a.get("class") or "").split():
            self._p = {"attrs": a, "text": ""}
            self.table_warnings.append(self._p)

    def handle_endtag(self, tag):
        if tag == "figure":
            self._figure = None
        elif tag == "div" and self._head_depth:
            self._head_depth -= 1
        elif tag == "p":
            self._p = None

    def handle_data(self, data):
        if self._figure is not None:
            self._figure["text"] += data
        if self._head_depth:
            self.head_text += data
        if self._p is not None:
            self._p["text"] += data


def md_cells(md):
    """The cells of the Markdown page's tables (split at unescaped pipes)."""
    cells = []
    for line in md.splitlines():
        if line.startswith("|"):
            cells += [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
    return cells


def check_flagged_page(out, r, when):
    """The page of the FLAGS recipes: exactly g/todo, g/black and the table's -H render flagged."""
    check(r.returncode == 3, f"{when}: flagged figures exit 3 (got {r.returncode}: {r.stderr.strip()!r})")
    lines = r.stderr.strip().splitlines()
    warned = sorted(re.search(r"figure (\S+)", l).group(1) for l in lines if "warning: figure" in l)
    check(warned == ["g/black", "g/todo", "t/cbempty_hemisphere"] and len(lines) == 3,
          f"{when}: one warning line per flagged figure on stderr (got {lines})")
    for l in lines:
        check(("all black" in l) if "g/black" in l else (TODO_LINE in l),
              f"{when}: the warning says why: {l!r}")
    m = json.load(open(os.path.join(out, "manifest.json")))
    check(m["summary"]["flagged"] == 3, f"{when}: 3 figures flagged in the summary (got {m['summary']['flagged']})")
    kinds = {f["name"]: [x["kind"] for x in f["flags"]] for f in m["figures"]}
    check(kinds == {"plain": [], "todo": ["todo"], "black": ["black"], "dim": [], "expected": []},
          f"{when}: the manifest flags todo (TODO line) and black (all black) only (got {kinds})")

    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    p = FlagParser()
    p.feed(page)
    figs = {os.path.basename(f["images"][0]): f for f in p.figures if f["images"]}
    check(sorted(figs) == ["black.png", "dim.png", "expected.png", "plain.png", "todo.png"],
          f"{when}: every figure shows its image (got {sorted(figs)})")
    for name, kind in (("todo", "todo"), ("black", "black")):
        f = figs.get(f"{name}.png", {"attrs": {}, "text": ""})
        check(f["attrs"].get("data-flagged") == kind and "flagged" in (f["attrs"].get("class") or ""),
              f"{when}: HTML figure {name} is marked flagged ({kind}) (got {f['attrs']})")
        check("Check this figure" in f["text"]
              and (TODO_LINE in f["text"] if kind == "todo" else "all black" in f["text"]),
              f"{when}: HTML figure {name} says why: {f['text']!r}")
    for name in ("plain", "dim", "expected"):
        f = figs.get(f"{name}.png", {"attrs": {}, "text": ""})
        check("data-flagged" not in f["attrs"] and "Check this figure" not in f["text"],
              f"{when}: HTML figure {name} is not flagged")
    check("Figures to check (3)" in p.head_text and TODO_LINE in p.head_text and "all black" in p.head_text,
          f"{when}: the list at the head of the HTML page names the problems: {p.head_text!r}")
    for name in ("g/todo", "g/black", "t/cbempty_hemisphere"):
        check(name in p.head_text, f"{when}: the HTML list names {name}")
    for name in ("g/plain", "g/dim", "g/expected", "t/cbempty_light"):
        check(name not in p.head_text, f"{when}: the HTML list leaves out {name}")
    check("#g" in p.head_links and "#t" in p.head_links, f"{when}: the HTML list links to the figures")
    check(len(p.table_warnings) == 1 and TODO_LINE in p.table_warnings[0]["text"]
          and "hemisphere" in p.table_warnings[0]["text"],
          f"{when}: the table names its flagged render under it ({[w['text'] for w in p.table_warnings]})")

    md = open(os.path.join(out, "index.md"), encoding="utf-8").read()
    head = md.split("**Figures to check (3):**", 1)
    check(len(head) == 2, f"{when}: the Markdown page lists the figures to check at its head")
    head = head[1].split("\n## ", 1)[0] if len(head) == 2 else ""
    items = [l for l in head.splitlines() if l.startswith("- ")]
    check(len(items) == 3, f"{when}: three Markdown list items (got {items})")
    for name, why in (("g/todo", TODO_LINE), ("g/black", "all black"), ("t/cbempty_hemisphere", TODO_LINE)):
        check(any(name in i and why in i for i in items), f"{when}: the Markdown list says {name}: {why}")
    cells = md_cells(md)
    for name, why in (("todo", TODO_LINE), ("black", "all black"), ("plain", None), ("dim", None),
                      ("expected", None)):
        cell = [c for c in cells if f"](img/g/{name}.png)" in c]
        ok = len(cell) == 1 and (("Check this figure" in cell[0] and why in cell[0]) if why
                                  else "Check this figure" not in cell[0])
        check(ok, f"{when}: the Markdown figure {name} is {'flagged: ' + why if why else 'not flagged'} ({cell})")
    return m


def test_flags(a):
    tmp = tempfile.mkdtemp(prefix="writeup-flags-")
    try:
        recipes = os.path.join(tmp, "figures.toml")
        out = os.path.join(tmp, "out")
        fake = os.path.join(tmp, "fake-pathtracer")
        with open(fake, "w") as f:
            f.write(FAKE.format(python=sys.executable, testdir=os.path.dirname(os.path.abspath(__file__)),
                                real=os.path.abspath(a.pathtracer)))
        os.chmod(fake, 0o755)
        with open(recipes, "w") as f:
            f.write(FLAGS.format(scenes=os.path.join(ROOT, "scenes")))
        cmd = [GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", fake, "--no-progress", "-t", "2"]
        r = run(cmd)
        m = check_flagged_page(out, r, "first run")
        check(m["summary"]["rendered"] == 7, f"first run renders all 7 (got {m['summary']['rendered']})")
        # Again: everything from the cache, flagged as before.
        r = run(cmd)
        m = check_flagged_page(out, r, "cached run")
        check((m["summary"]["rendered"], m["summary"]["cached"]) == (0, 7),
              f"the second run renders nothing (got {m['summary']['rendered']} rendered)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


REFERENCE = """
[settings]
scenes_dir = "{scenes}"
size = [24, 18]
seed = 2

[[section]]
id = "s"

[[section.grid]]
id = "g"
scene = "CBspheres_lambertian.dae"
args = "--part 4 -s 1 -l 1 -m 2"
cells = [
  {{ label = "lit" }},
  {{ label = "dark, expected", args = "--indirect-only -m 1", expect_black = true }},
  {cells}
]
"""


def test_reference(a):
    tmp = tempfile.mkdtemp(prefix="writeup-reference-")
    try:
        recipes = os.path.join(tmp, "figures.toml")
        out = os.path.join(tmp, "out")

        def generate(cells=""):
            with open(recipes, "w") as f:
                f.write(REFERENCE.format(scenes=os.path.join(ROOT, "scenes"), cells=cells))
            r = run([GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", a.pathtracer, "--no-progress"])
            m = json.load(open(os.path.join(out, "manifest.json")))
            return r, {f["name"]: [x["kind"] for x in f["flags"]] for f in m["figures"]}

        r, flags = generate()
        check(r.returncode == 0 and r.stderr == "", f"reference renders: exit 0, nothing on stderr "
                                                    f"(got {r.returncode}: {r.stderr.strip()!r})")
        check(flags == {"lit": [], "dark_expected": []}, f"no figure flagged (got {flags})")
        page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
        md = open(os.path.join(out, "index.md"), encoding="utf-8").read()
        check("Check this figure" not in page and "Figures to check" not in page
              and "Check this figure" not in md and "Figures to check" not in md, "the page flags nothing")
        # The same black render (--indirect-only -m 1 has no light), once without expect_black:
        # it is the renderer's own PNG that reads as black.
        r, flags = generate('{ label = "dark" , args = "--indirect-only -m 1" },')
        check(r.returncode == 3, f"an unexpected black reference render exits 3 (got {r.returncode})")
        check(flags == {"lit": [], "dark_expected": [], "dark": ["black"]},
              f"only the unexpected black figure is flagged (got {flags})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


# Fixed times in prose: "takes about 2 s", "in about a second", "milliseconds",
# "hundreds of times faster", "50x faster".
TIME_CLAIMS = [
    r"\b\d[\d,.]*\s*(ms|s|secs?|seconds?|milliseconds?|minutes?|mins?|hours?|h)\b",
    r"\b(in|about|under|within|takes?|took|over)\s+(about\s+)?(a|an|one|half a|a few)\s+"
    r"(milli)?(second|minute|hour)s?\b",
    r"\b(milli|micro)?seconds\b", r"\bminutes?\b", r"\bhours?\b",
    r"\b(times|×|x)\s+(faster|slower|quicker)\b", r"\b(hundreds|thousands|tens) of times\b",
    r"\b\d[\d,.]*\s*(×|x)(?!\s*\d)",     # a speed-up, not a size like 128 x 96
]


def time_claims(text):
    text = " ".join(text.split())
    return [m.group(0) for p in TIME_CLAIMS for m in re.finditer(p, text, re.I)]


def test_text(a):
    # The patterns find the kind of sentence they are for.
    for sentence in ("meshes render in about a second", "The BVH renders take milliseconds",
                     "it takes about 2 s", "hundreds of times faster", "a 50x speed-up"):
        check(time_claims(sentence), f"the check finds a fixed time in {sentence!r}")
    check(not time_claims("the second bounce lights the ceiling; compare the render times under the images"),
          "the check leaves other prose alone")
    with open(RECIPES, "rb") as f:
        data = tomllib.load(f)
    n = 0
    for sec in data["section"]:
        for item in [sec] + sec.get("grid", []) + sec.get("table", []):
            for key in ("title", "text"):
                claims = time_claims(item.get(key, ""))
                check(not claims, f"{item.get('id')}: its {key} states no fixed time (found {claims})")
                n += 1
    print(f"{n} texts checked")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["quick", "browser", "cache", "errors", "flags", "reference", "png", "text"])
    ap.add_argument("--pathtracer")
    ap.add_argument("--artifacts", default=os.path.join(ROOT, "build", "test-artifacts", "writeup"))
    a = ap.parse_args()
    if a.what not in ("browser", "png", "text") and not (a.pathtracer and os.path.isfile(a.pathtracer)):
        print(f"FAIL: no pathtracer binary: {a.pathtracer}")
        return 1
    {"quick": test_quick, "browser": test_browser, "cache": test_cache, "errors": test_errors,
     "flags": test_flags, "reference": test_reference, "png": test_png, "text": test_text}[a.what](a)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
