#!/usr/bin/env python3
"""End-to-end tests of the write-up figure generator (writeup/make_figures.py).

    test_writeup.py quick     --pathtracer EXE --artifacts DIR
    test_writeup.py browser   --artifacts DIR
    test_writeup.py cache     --pathtracer EXE
    test_writeup.py errors    --pathtracer EXE
    test_writeup.py flags     --pathtracer EXE
    test_writeup.py reference --pathtracer EXE
    test_writeup.py stats     --pathtracer EXE
    test_writeup.py text
    test_writeup.py bvh       --pathtracer EXE

quick:   a --quick run of the real recipes into DIR/quick: every figure
         rendered, each a preview of its whole view (its -r size shrunk to
         at most 120 x 90; the BVH figures at their size), every image the
         page references exists, every table cell a number, nothing
         flagged, every expect_black figure black.
browser: that page in headless Chromium: it loads, every image loads, no
         errors; screenshots DIR/page.png (1280 x 2000) and DIR/page_full.png.
cache:   a second run renders nothing; changing one recipe re-renders only
         that render; another binary re-renders everything.
errors:  bad recipes and a missing binary give one line naming the recipe or
         file and exit 2; a failed render is a failed figure on the page and
         exit 1.
flags, reference, stats: see test_flags.py (figures flagged for a TODO line
         or an all-black image, and the renderer's max_radiance).
text:    the recipes' prose states no fixed render times or speed-ups.
bvh:     see test_bvh_figures.py (--bvh-boxes and --bvh-node draw the
         render's BVH boxes where the camera projects them; the
         p2_bvh_boxes figures show them).

The modules of the generator's package have unit tests of their own:
test_recipes.py, test_cache.py, test_scheduler.py, test_checks.py,
test_page.py.
"""

import argparse
import json
import os
import re
import shutil
import struct
import sys
import tempfile
import tomllib

sys.dont_write_bytecode = True
from support import (CHECKER, GENERATOR, RECIPES, ROOT, PageParser, check, expected_items,  # noqa: E402
                     failures, run, scaled_seconds, summary)
import test_bvh_figures  # noqa: E402
import test_flags  # noqa: E402

NUMBER = re.compile(r"^-?[0-9][0-9,]*(\.[0-9]+)?×?$")


def png_size(path):
    """(width, height) from a PNG's header."""
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24]) if head[:8] == b"\x89PNG\r\n\x1a\n" else None


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
        # A preview of the whole view: rendered at the figure's size (-r), then
        # shrunk to at most 120 x 90; the BVH figures' boxes keep them full size.
        size = re.search(r" -r (\d+) (\d+) ", f["command"])
        if check(size, f"{f['grid']}/{f['name']}: the command gives -r") and f["image"]:
            w, h = (int(v) for v in size.groups())
            k = 1 if "--bvh-" in f["command"] else max(-(-w // 120), -(-h // 90))
            check(png_size(os.path.join(out, f["image"])) == (w // k, h // k),
                  f"{f['grid']}/{f['name']}: a {w // k} x {h // k} preview of the {w} x {h} view "
                  f"(got {png_size(os.path.join(out, f['image']))})")
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
    for f in figures:
        check(f["flags"] == [], f"{f['grid']}/{f['name']} is not flagged (got {f['flags']})")
        check(isinstance(f["max_radiance"], (int, float)),
              f"{f['grid']}/{f['name']}: the renderer reported its max_radiance (got {f['max_radiance']!r})")
        if f["expect_black"]:
            check(f["max_radiance"] == 0, f"{f['grid']}/{f['name']} is expected to be black and is "
                                          f"(max_radiance {f['max_radiance']})")
    check("Figures to check" not in open(os.path.join(out, "index.html"), encoding="utf-8").read()
          and "Figures to check" not in md, "no list of figures to check on the page")


def test_browser(a):
    page = os.path.join(a.artifacts, "quick", "index.html")
    shot = os.path.join(a.artifacts, "page.png")
    full = os.path.join(a.artifacts, "page_full.png")
    if not os.path.exists("/usr/bin/chromium") and not shutil.which("chromium"):
        check(False, "chromium is not installed: run scripts/setup.sh (as root) to install it")
        return
    # check_page.py's limit on each Chromium run (180 s by default), scaled.
    r = run([CHECKER, page, "--screenshot", shot, "--full-screenshot", full, "--timeout", str(scaled_seconds(180))])
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




TESTS = {"quick": test_quick, "browser": test_browser, "cache": test_cache, "errors": test_errors,
         "flags": test_flags.test_flags, "reference": test_flags.test_reference,
         "stats": test_flags.test_stats, "text": test_text, "bvh": test_bvh_figures.test_boxes}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=list(TESTS))
    ap.add_argument("--pathtracer")
    ap.add_argument("--artifacts", default=os.path.join(ROOT, "build", "test-artifacts", "writeup"))
    a = ap.parse_args()
    if a.what not in ("browser", "text") and not (a.pathtracer and os.path.isfile(a.pathtracer)):
        print(f"FAIL: no pathtracer binary: {a.pathtracer}")
        return 1
    TESTS[a.what](a)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
