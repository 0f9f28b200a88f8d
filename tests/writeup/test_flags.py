"""Flagged figures (TODO lines, all-black images) and the renderer figure the
all-black check reads (max_radiance in --stats-json). Run through
test_writeup.py:

flags:     with a fake pathtracer that prints a TODO line for some renders and
           reports max_radiance 0 for others, those figures are flagged in the
           HTML and the Markdown page (at the figure and in the list at the
           head) and the run exits 3, again from the cache; the other
           figures, one of them reporting the smallest positive max_radiance
           with an all-black PNG, are not flagged: the flag follows
           max_radiance, not the PNG.
reference: with the real pathtracer, a lit render is not flagged, a black
           one is (max_radiance 0 as the renderer reports it), and not where
           the recipe says expect_black.
stats:     the pathtracer's --stats-json holds max_radiance, the largest
           radiance channel of the image before tone mapping, equal to the
           largest value of its --pfm output: 0 for a black render, the
           light's emission (above 1) where the light is seen.
"""

import html.parser
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

from support import GENERATOR, ROOT, SCENES, check, run

TODO_LINE = ("TODO: implement Part 3: estimate_direct_lighting_hemisphere "
             "(stages/part3_direct_lighting/direct_lighting.cpp)")

FAKE = """#!{python}
# A pathtracer for the write-up tests (tests/writeup/test_flags.py, fake_pathtracer).
import sys
sys.dont_write_bytecode = True
sys.path.insert(0, {testdir!r})
import test_flags
sys.exit(test_flags.fake_pathtracer({real!r}, sys.argv[1:]))
"""

# The smallest positive float32: an image this bright somewhere is not black,
# even though its PNG is.
SMALLEST_RADIANCE = struct.unpack("<f", struct.pack("<I", 1))[0]


def write_black_png(path, width, height):
    """An all-black 8-bit RGB PNG."""
    raw = b"".join(b"\0" + bytes(3 * width) for _ in range(height))
    chunks = [(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)),
              (b"IDAT", zlib.compress(raw)), (b"IEND", b"")]
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + b"".join(struct.pack(">I", len(body)) + kind + body
                                               + struct.pack(">I", zlib.crc32(kind + body))
                                               for kind, body in chunks))


def set_max_radiance(stats_path, value):
    with open(stats_path) as f:
        stats = json.load(f)
    stats["max_radiance"] = value
    with open(stats_path, "w") as f:
        json.dump(stats, f)


def fake_pathtracer(real, args):
    """Renders with the real pathtracer, except that
       -H             first prints a TODO line on stderr, as a starter-kit build does
                      the first time it reaches a function not written yet;
       --no-rr        then reports max_radiance 0 (the image is left as rendered);
       --direct-only  then reports the smallest positive max_radiance and
                      replaces the image with an all-black one."""
    if "-H" in args:
        sys.stderr.write(TODO_LINE + "\n")
        sys.stderr.flush()
    rc = subprocess.call([real] + args)
    if rc != 0:
        return rc
    out = args[args.index("-f") + 1]
    stats = args[args.index("--stats-json") + 1]
    i = args.index("-r")
    width, height = int(args[i + 1]), int(args[i + 2])
    if "--no-rr" in args:
        set_max_radiance(stats, 0)
    elif "--direct-only" in args:
        set_max_radiance(stats, SMALLEST_RADIANCE)
        write_black_png(out, width, height)
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
                f.write(REFERENCE.format(scenes=SCENES, cells=cells))
            r = run([GENERATOR, "--recipes", recipes, "--out", out, "--pathtracer", a.pathtracer, "--no-progress"])
            with open(os.path.join(out, "manifest.json")) as f:
                m = json.load(f)
            return (r, {f["name"]: [x["kind"] for x in f["flags"]] for f in m["figures"]},
                    {f["name"]: f["max_radiance"] for f in m["figures"]})

        r, flags, radiance = generate()
        check(r.returncode == 0 and r.stderr == "", f"reference renders: exit 0, nothing on stderr "
                                                    f"(got {r.returncode}: {r.stderr.strip()!r})")
        check(flags == {"lit": [], "dark_expected": []}, f"no figure flagged (got {flags})")
        check(radiance["lit"] > 0 and radiance["dark_expected"] == 0,
              f"the renderer reports max_radiance above 0 for the lit render, 0 for the dark one (got {radiance})")
        page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
        md = open(os.path.join(out, "index.md"), encoding="utf-8").read()
        check("Check this figure" not in page and "Figures to check" not in page
              and "Check this figure" not in md and "Figures to check" not in md, "the page flags nothing")
        # The same black render (--indirect-only -m 1 has no light), once without expect_black:
        # it is the renderer's own max_radiance that says black.
        r, flags, radiance = generate('{ label = "dark" , args = "--indirect-only -m 1" },')
        check(r.returncode == 3, f"an unexpected black reference render exits 3 (got {r.returncode})")
        check(flags == {"lit": [], "dark_expected": [], "dark": ["black"]},
              f"only the unexpected black figure is flagged (got {flags})")
        check(radiance["dark"] == 0, f"the flagged figure's max_radiance is 0 (got {radiance['dark']})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def read_pfm(path):
    """The channel values of a little-endian colour PFM, as float32 read into floats."""
    with open(path, "rb") as f:
        data = f.read()
    magic, size, scale, body = data.split(b"\n", 3)
    width, height = map(int, size.split())
    assert magic == b"PF" and float(scale) < 0, f"{path}: not a little-endian colour PFM"
    return struct.unpack(f"<{width * height * 3}f", body[:width * height * 12])


def as_float32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def test_stats(a):
    """max_radiance in --stats-json against the --pfm of the same render."""
    tmp = tempfile.mkdtemp(prefix="writeup-stats-")
    try:
        cases = [
            ("lit", "CBspheres_lambertian.dae", "--part 4 -s 2 -l 1 -m 2 -r 40 30", lambda v: 0 < v),
            ("black", "CBspheres_lambertian.dae", "--part 4 -s 2 -l 1 -m 1 --indirect-only -r 40 30",
             lambda v: v == 0),
            # Part 3 at the course's full view with -m 0: the emission alone, the light in view.
            ("light in view", "CBspheres_lambertian.dae", "--part 3 -s 1 -m 0 -r 800 600", lambda v: v > 1),
            ("one cell", "CBbunny.dae", "--part 3 -s 1 -l 1 -r 40 30 -p 8 8 8 8", lambda v: 0 < v),
        ]
        for what, scene, args, expect in cases:
            cmd = [a.pathtracer] + args.split() + ["--no-progress", "--stats-json", "s.json", "--pfm", "s.pfm",
                                                   "-f", "s.png", os.path.join(SCENES, scene)]
            r = subprocess.run(cmd, cwd=tmp, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if not check(r.returncode == 0, f"{what}: the render succeeds ({r.stderr.strip()!r})"):
                continue
            with open(os.path.join(tmp, "s.json")) as f:
                stats = json.load(f)
            v = stats.get("max_radiance")
            if not check(isinstance(v, (int, float)) and not isinstance(v, bool),
                         f"{what}: --stats-json holds a numeric max_radiance (got {v!r})"):
                continue
            finite = [x for x in read_pfm(os.path.join(tmp, "s.pfm")) if x == x and abs(x) != float("inf")]
            largest = max([0.0] + finite)
            check(as_float32(v) == largest,
                  f"{what}: max_radiance {v!r} is the largest radiance channel of the --pfm image ({largest!r})")
            check(expect(v), f"{what}: max_radiance {v!r} is as expected for this render")
            print(f"{what}: max_radiance {v!r}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
