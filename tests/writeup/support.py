"""What the write-up tests share: paths, the failure list, running the
generator, importing its package, and parsers of the page it writes."""

import html.parser
import json
import os
import subprocess
import sys
import time
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GENERATOR = os.path.join(ROOT, "writeup", "make_figures.py")
CHECKER = os.path.join(ROOT, "writeup", "check_page.py")
RECIPES = os.path.join(ROOT, "writeup", "figures.toml")
SCENES = os.path.join(ROOT, "scenes")

failures = []


def import_generator():
    """The generator's package (writeup/generator), importable by name."""
    sys.dont_write_bytecode = True  # nothing written into the source tree
    path = os.path.join(ROOT, "writeup")
    if path not in sys.path:
        sys.path.insert(0, path)
    import generator  # noqa: F401
    return generator


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}", flush=True)
    return cond


def scaled_seconds(seconds):
    """`seconds` times PT_TEST_TIMEOUT_SCALE (tests/timeout_scale/timeout_scale.py)."""
    path = os.path.join(ROOT, "tests", "timeout_scale")
    if path not in sys.path:
        sys.path.insert(0, path)
    import timeout_scale
    return timeout_scale.scaled_seconds(seconds)


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


def summary(out):
    with open(os.path.join(out, "manifest.json")) as f:
        return json.load(f)["summary"]

