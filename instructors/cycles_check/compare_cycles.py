#!/usr/bin/env python3
"""Does our renderer draw a scene as Blender's Cycles draws it?

A second opinion from an independent renderer: the same scene (read by our
loader and rebuilt in Cycles by cycles_scene.py), K renders by each at
independent seeds, compared in linear radiance block by block.

The image is cut into a grid (--grid 8 6: 8 columns, 6 rows). For every
block and colour channel, our K block means (mean a, spread s_a) are set
against Cycles' K (mean b, spread s_b) by Welch's t,

    t = (b - a) / sqrt(s_a^2 / K + s_b^2 / K),

with Welch's degrees of freedom rounded down; two-sided p values, Holm's
step-down over all blocks x 3 channels at --alpha. The whole image's mean
per channel is tested the same way (3 comparisons, Holm at --alpha).
A block is also reported by its size: b / a - 1.

  compare_cycles.py --scene DAE -s N -l N -m N [-r W H] [-K 8]
                    [-e MAP.exr] [-b R] [-d D] [--part 9] [--extra=FLAGS]
                    [--grid 8 6] [--alpha 0.05] [--work DIR] [--keep]
                    [--figure PNG] [--markdown FILE --title T]

Cycles renders with -s samples per pixel, Cycles' own light sampling (it
has no -l) and -m translated (cycles_scene.py). Needs Blender (Debian's
blender package) on PATH and build/bin/pathtracer and build/bin/scene_json
(cmake --build build --target pathtracer scene_json).
"""
import argparse
import math
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "instructors", "course_scenes"))
from compare_staff import block_means, holm, t_two_sided_p, write_png  # noqa: E402


def read_pfm(path):
    """-> H x W x 3 float array, top row first."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise SystemExit("compare_cycles.py: %s: not a colour PFM" % path)
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    if data.size != w * h * 3:
        raise SystemExit("compare_cycles.py: %s: truncated" % path)
    return data.reshape(h, w, 3)[::-1].astype(np.float64)


def run(cmd, what):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        tail = "\n".join(r.stdout.splitlines()[-15:])
        raise SystemExit("compare_cycles.py: %s failed (exit %d):\n%s" % (what, r.returncode, tail))
    return r.stdout


def welch(a, b):
    """a, b: K x ... samples. -> t, p (elementwise)."""
    k_a, k_b = a.shape[0], b.shape[0]
    va, vb = a.var(axis=0, ddof=1) / k_a, b.var(axis=0, ddof=1) / k_b
    se = np.sqrt(va + vb)
    diff = b.mean(axis=0) - a.mean(axis=0)
    t = np.where(se > 0, diff / np.where(se > 0, se, 1), np.where(diff == 0, 0.0, np.inf))
    df = np.where(se > 0, (va + vb) ** 2 / np.maximum(va ** 2 / (k_a - 1) + vb ** 2 / (k_b - 1), 1e-300), k_a - 1)
    p = np.vectorize(lambda tt, dd: t_two_sided_p(tt, max(1, int(math.floor(dd)))))(t, df)
    return t, p


def tone(img):
    return (255 * np.clip(img, 0, 1) ** (1 / 2.2) + 0.5).astype(np.uint8)


def figure(path, ours, cyc, ratio, flagged, xs, ys):
    """ours | Cycles | each block's b / a - 1 (grey 0, red Cycles brighter,
    blue darker, full colour at 5 %), flagged blocks outlined in yellow."""
    h, w, _ = ours.shape
    diff = np.full((h, w, 3), 128, np.uint8)
    rows, cols = ratio.shape[:2]
    for r in range(rows):
        for c in range(cols):
            d = float(np.clip((ratio[r, c].mean() - 1) / 0.05, -1, 1))
            diff[ys[r]:ys[r + 1], xs[c]:xs[c + 1]] = np.array(
                (128 + 127 * d, 128 - 127 * abs(d), 128 - 127 * d)).clip(0, 255).astype(np.uint8)
            if flagged[r, c].any():
                for y0, y1, x0, x1 in ((ys[r], ys[r] + 2, xs[c], xs[c + 1]), (ys[r + 1] - 2, ys[r + 1], xs[c], xs[c + 1]),
                                       (ys[r], ys[r + 1], xs[c], xs[c] + 2), (ys[r], ys[r + 1], xs[c + 1] - 2, xs[c + 1])):
                    diff[y0:y1, x0:x1] = (255, 230, 0)
    gap = np.full((h, 4, 3), 255, np.uint8)
    write_png(path, np.concatenate([tone(ours), gap, tone(cyc), gap, diff], axis=1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True)
    ap.add_argument("-s", type=int, required=True)
    ap.add_argument("-l", type=int, required=True)
    ap.add_argument("-m", type=int, required=True)
    ap.add_argument("-r", type=int, nargs=2, default=[320, 240])
    ap.add_argument("-K", type=int, default=8)
    ap.add_argument("-e", default=None)
    ap.add_argument("-b", type=float, default=None)
    ap.add_argument("-d", type=float, default=None)
    ap.add_argument("--part", type=int, default=9)
    ap.add_argument("--extra", default="", help="more flags for our pathtracer")
    ap.add_argument("--grid", type=int, nargs=2, default=[8, 6])
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--work", default=None)
    ap.add_argument("--figure", default=None)
    ap.add_argument("--markdown", default=None)
    ap.add_argument("--title", default=None)
    ap.add_argument("--pathtracer", default=os.path.join(ROOT, "build", "bin", "pathtracer"))
    ap.add_argument("--scene-json", default=os.path.join(ROOT, "build", "bin", "scene_json"))
    ap.add_argument("--blender", default="blender")
    args = ap.parse_args()
    if args.K < 2:
        ap.error("-K must be at least 2 (the spread needs two renders)")
    if args.markdown and not args.title:
        ap.error("--markdown needs --title")

    work = args.work or tempfile.mkdtemp(prefix="cycles_check.")
    os.makedirs(work, exist_ok=True)
    w, h = args.r
    lens = []
    if args.e:
        lens += ["-e", args.e]
    if args.b is not None:
        lens += ["-b", str(args.b)]
    if args.d is not None:
        lens += ["-d", str(args.d)]
    scene_json = os.path.join(work, "scene.json")
    run([args.scene_json, args.scene, str(w), str(h), scene_json] + lens, "scene_json")

    ours, cyc = [], []
    for k in range(args.K):
        pfm = os.path.join(work, "ours_%d.pfm" % k)
        print("compare_cycles.py: ours, render %d of %d" % (k + 1, args.K), file=sys.stderr)
        run([args.pathtracer, "--part", str(args.part), "-t", str(args.threads), "-s", str(args.s), "-l", str(args.l),
             "-m", str(args.m), "-r", str(w), str(h), "--seed", str(1000 + k), "--no-progress",
             "-f", os.path.join(work, "ours.png"), "--pfm", pfm] + lens + shlex.split(args.extra) + [args.scene],
            "our render")
        ours.append(read_pfm(pfm))
    for k in range(args.K):
        pfm = os.path.join(work, "cycles_%d.pfm" % k)
        print("compare_cycles.py: Cycles, render %d of %d" % (k + 1, args.K), file=sys.stderr)
        run([args.blender, "-b", "--factory-startup", "-noaudio", "--python", os.path.join(HERE, "cycles_scene.py"),
             "--", scene_json, pfm, "--samples", str(args.s), "--max-depth", str(args.m), "--seed", str(k),
             "--threads", str(args.threads)], "Cycles render")
        cyc.append(read_pfm(pfm))
    ours, cyc = np.array(ours), np.array(cyc)

    cols, rows = args.grid
    bo = np.array([block_means(o, cols, rows)[0] for o in ours])
    bc = np.array([block_means(c, cols, rows)[0] for c in cyc])
    _, xs, ys = block_means(ours[0], cols, rows)
    t, p = welch(bo, bc)
    flagged = np.array(holm(p.ravel().tolist(), args.alpha)).reshape(p.shape)
    ratio = bc.mean(axis=0) / np.maximum(bo.mean(axis=0), 1e-12)
    go, gc = ours.mean(axis=(1, 2)), cyc.mean(axis=(1, 2))
    gt, gp = welch(go, gc)
    gflag = holm(gp.tolist(), args.alpha)
    gratio = gc.mean(axis=0) / go.mean(axis=0)

    mean_o, mean_c = ours.mean(axis=0), cyc.mean(axis=0)
    if args.figure:
        figure(args.figure, mean_o, mean_c, ratio, flagged, xs, ys)

    n_flag = int(flagged.any(axis=2).sum())
    worst = np.unravel_index(np.argmin(p), p.shape)
    lines = [
        "scene %s, %dx%d, -s %d -l %d -m %d%s, K = %d each" % (args.scene, w, h, args.s, args.l, args.m,
                                                                (" " + " ".join(lens)) if lens else "", args.K),
        "blocks that differ (Holm, alpha %.2f over %d): %d of %d" % (args.alpha, p.size, n_flag, rows * cols),
        "whole-image mean, Cycles / ours: %s (%s)" % (" ".join("%.4f" % r for r in gratio),
                                                     "differs" if any(gflag) else "not significant"),
        "block ratios Cycles / ours: %.4f to %.4f (median %.4f); mean t^2 %.2f" % (
            ratio.min(), ratio.max(), float(np.median(ratio)), float(np.mean(np.minimum(t, 1e6) ** 2))),
        "smallest p: block (col %d, row %d from the top) channel %d: ratio %.4f, t %.2f, p %.2g" % (
            worst[1], worst[0], worst[2], ratio[worst], t[worst], p[worst]),
    ]
    print("\n".join(lines))
    if args.markdown:
        with open(args.markdown, "a") as f:
            f.write("\n### %s\n\n" % args.title)
            for line in lines:
                f.write("- %s\n" % line)
            if n_flag:
                f.write("\n| block (col, row) | channel | Cycles / ours | t | p |\n|---|---|---:|---:|---:|\n")
                for r, c, ch in zip(*np.nonzero(flagged)):
                    f.write("| (%d, %d) | %s | %.4f | %.2f | %.2g |\n" % (c, r, "RGB"[ch], ratio[r, c, ch], t[r, c, ch],
                                                                       p[r, c, ch]))
    if not args.work:
        import shutil
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
