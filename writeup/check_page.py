#!/usr/bin/env python3
"""Check the write-up page in a real browser (headless Chromium).

    python3 writeup/check_page.py [PAGE.html] [--screenshot PNG] [--full-screenshot PNG]

Loads a copy of the page with a small script added that, once the page has
loaded, lists every <img> that did not load (complete && naturalWidth > 0
is false) and every error event (JavaScript errors, resources that failed),
and writes that list into the DOM; Chromium dumps the DOM and this script
reads the list back. Then it takes a screenshot of the page as it is
(1280 x 2000 by default) and, with --full-screenshot, one of its whole
length. Exit status 0 when every image loaded and nothing failed, 1
otherwise (with one line per problem), 2 for bad usage or no Chromium.
"""

import argparse
import html
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROG = "check_page.py"
MARKER_ID = "page-check-result"

PROBE = """<script>
(function () {
  var errors = [];
  window.onerror = function (msg, src, line) { errors.push("javascript error: " + msg + " (" + src + ":" + line + ")"); };
  window.addEventListener("error", function (e) {
    var t = e.target;
    if (t && t !== window && t.tagName) errors.push("failed to load <" + t.tagName.toLowerCase() + "> " + (t.getAttribute("src") || t.getAttribute("href")));
  }, true);
  window.addEventListener("load", function () {
    var broken = [], imgs = document.images;
    for (var i = 0; i < imgs.length; i++) {
      if (!(imgs[i].complete && imgs[i].naturalWidth > 0)) broken.push(imgs[i].getAttribute("src"));
    }
    var out = document.createElement("pre");
    out.id = "%s";
    out.textContent = JSON.stringify({images: imgs.length, broken: broken, errors: errors,
                                      height: Math.ceil(document.documentElement.scrollHeight)});
    document.body.appendChild(out);
  });
})();
</script>
""" % MARKER_ID


def find_chromium(explicit):
    for c in [explicit] if explicit else ["/usr/bin/chromium", "chromium", "chromium-browser"]:
        p = shutil.which(c) if not os.path.isabs(c) else (c if os.access(c, os.X_OK) else None)
        if p:
            return p
    return None


def chromium(exe, profile, args, timeout):
    cmd = [exe, "--headless", "--disable-gpu", "--no-sandbox", "--no-first-run", "--disable-extensions",
           "--hide-scrollbars", f"--user-data-dir={profile}"] + args
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout,
                          stdin=subprocess.DEVNULL)


class CheckFailed(Exception):
    """The page could not be checked: one line, exit status 1."""


def parse_args(argv):
    ap = argparse.ArgumentParser(prog=PROG, description="Check the write-up page in headless Chromium.")
    ap.add_argument("page", nargs="?", default=os.path.join(ROOT, "writeup", "out", "index.html"))
    ap.add_argument("--screenshot", help="write a 1280 x 2000 screenshot of the page here")
    ap.add_argument("--full-screenshot", help="write a screenshot of the whole page here")
    ap.add_argument("--window-size", default="1280,2000", help="screenshot size (default 1280,2000)")
    ap.add_argument("--chromium", help="the browser (default /usr/bin/chromium)")
    ap.add_argument("--timeout", type=float, default=180, help="seconds per browser run (default 180)")
    return ap.parse_args(argv)


def probe(exe, profile, probe_page, timeout):
    """What the probe script found in the loaded page: {"broken", "errors", "images", "height"}."""
    try:
        r = chromium(exe, profile, ["--virtual-time-budget=20000", "--dump-dom", "file://" + probe_page], timeout)
    except subprocess.TimeoutExpired:
        raise CheckFailed(f"chromium did not finish within {timeout:g} s")
    dom = r.stdout.decode("utf-8", "replace")
    m = re.search(r'<pre id="%s">(.*?)</pre>' % MARKER_ID, dom, re.S)
    if r.returncode != 0 or not m:
        tail = r.stderr.decode("utf-8", "replace").strip().splitlines()[-3:]
        raise CheckFailed(f"the page did not finish loading in chromium (exit {r.returncode}); {' | '.join(tail)}")
    return json.loads(html.unescape(m.group(1)))


def screenshot(exe, profile, page, path, size, timeout):
    """Takes a screenshot of the page; a problem (text) or None."""
    path = os.path.abspath(path)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if os.path.exists(path):
        os.remove(path)
    try:
        chromium(exe, profile, [f"--screenshot={path}", f"--window-size={size}",
                                "--virtual-time-budget=20000", "file://" + page], timeout)
    except subprocess.TimeoutExpired:
        return f"screenshot {path}: chromium did not finish within {timeout:g} s"
    with open(path, "rb") if os.path.isfile(path) else open(os.devnull, "rb") as f:
        head = f.read(8)
    if head != b"\x89PNG\r\n\x1a\n":
        return f"screenshot {path}: chromium wrote no PNG"
    print(f"{PROG}: screenshot: {path}")
    return None


def check(a, exe, page, text):
    """The page's problems (empty when it is fine) and the probe's result."""
    n_img_source = len(re.findall(r"<img\b", text))
    problems = []
    # The copy sits beside the page so that its relative image paths resolve the same way.
    fd, probe_page = tempfile.mkstemp(prefix=".check-", suffix=".html", dir=os.path.dirname(page))
    profile = tempfile.mkdtemp(prefix="check-page-chromium-")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text.replace("<head>", "<head>\n" + PROBE, 1))
        result = probe(exe, profile, probe_page, a.timeout)
        for src in result["broken"]:
            problems.append(f"image did not load: {src}")
        for e in result["errors"]:
            problems.append(e)
        if result["images"] != n_img_source:
            problems.append(f"the browser saw {result['images']} images, the page has {n_img_source} <img> tags")
        for path, size in ((a.screenshot, a.window_size),
                           (a.full_screenshot, f"1280,{max(600, min(int(result['height']), 32000))}")):
            if path:
                problem = screenshot(exe, profile, page, path, size, a.timeout)
                if problem:
                    problems.append(problem)
    finally:
        os.remove(probe_page)
        shutil.rmtree(profile, ignore_errors=True)
    return problems, result


def main(argv=None):
    a = parse_args(argv)
    page = os.path.abspath(a.page)
    if not os.path.isfile(page):
        print(f"{PROG}: error: {a.page}: no such page (run writeup/make_figures.py first)", file=sys.stderr)
        return 2
    exe = find_chromium(a.chromium)
    if not exe:
        print(f"{PROG}: error: chromium not found; run scripts/setup.sh (as root) to install it "
              f"(Debian package 'chromium')", file=sys.stderr)
        return 2
    with open(page, encoding="utf-8") as f:
        text = f.read()
    if "<head>" not in text:
        print(f"{PROG}: error: {a.page}: no <head> to add the check to", file=sys.stderr)
        return 1
    try:
        problems, result = check(a, exe, page, text)
    except CheckFailed as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    for p in problems:
        print(f"{PROG}: error: {a.page}: {p}", file=sys.stderr)
    if problems:
        return 1
    print(f"{PROG}: {a.page}: loaded in chromium, {result['images']} images, all loaded, no errors")
    return 0


if __name__ == "__main__":
    sys.exit(main())
