#!/usr/bin/env python3
"""Is a build's expected image the reference's? Judged apart from the grader.

For each Monte Carlo case named, renders every build at --renders seeds (the
exact command `grader compare --list` prints, -t 1) and compares, per colour
channel:
  - the image mean: the build's mean over its renders against the mean of
    reference_images/<case>/mean.pfm, z = difference / sqrt(se_build^2 +
    se_ref^2), se_build from the spread of its renders' image means, se_ref
    from variance.pfm (100 renders);
  - the mean image, block by block (8 x 8 pixels): each block's mean over the
    renders against the reference's, with the standard error of the build's
    block means across its renders (a t statistic with renders - 1 degrees
    of freedom) and the reference's, plus float round-off (1e-6 of the
    value); "blocks off" counts blocks beyond the Sidak threshold for
    alpha = 0.01 over all blocks and channels (normal approximation), and
    mean z^2 should be near (n - 1) / (n - 3), 1.12 at 20 renders.
Each build renders at its own seeds, --first-seed + 100 * (crc32(NAME) %
10000) onward, so builds that draw the same random numbers are judged
independently. For a deterministic case (normal shading at one sample) each
build renders once and is compared by value: the largest difference and the
share of channels beyond 1e-3 + 1e-3 |m| (the grader's own rule). A render
with NaN or infinite pixels is reported as such.

--paired renders every build once at the same seed and reports how much of
each image is bit-identical to the first build's: a variant that changes
only how the answers are found (another BVH, shadow rays by closest hit)
draws the same random numbers and so renders exactly the reference's image.

  check_unbiased.py --build NAME=PATH [--build ...] --case CASE [--case ...]
                    [--renders 20] [--first-seed 3000] [-j 2] [--work DIR]
                    [--json FILE] [--table FILE] [--reuse]
  check_unbiased.py --paired --build NAME=PATH ... --case CASE ... [--first-seed S]

Run the reference build too (NAME=build/bin/pathtracer), first: it is the
control, the figures a correct build shows at this number of renders.
"""
import argparse
import concurrent.futures
import datetime
import json
import math
import os
import shlex
import struct
import subprocess
import sys
import zlib
from statistics import NormalDist

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def read_pfm(path):
    """(width, height, floats) of a colour PFM, rows bottom first as stored."""
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    if len(parts) < 4 or parts[0].strip() != b"PF":
        raise ValueError(f"{path}: not a colour PFM")
    w, h = (int(v) for v in parts[1].split())
    scale = float(parts[2])
    raw = parts[3][: 12 * w * h]
    if len(raw) != 12 * w * h:
        raise ValueError(f"{path}: truncated")
    fmt = ("<" if scale < 0 else ">") + f"{3 * w * h}f"
    return w, h, struct.unpack(fmt, raw)


def case_commands(grader):
    """case name -> its pathtracer argument list (without the binary)."""
    out = subprocess.run([grader, "compare", "--list"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    cmds = {}
    for line in out.splitlines():
        words = line.split()
        if len(words) > 2 and words[1].endswith("pathtracer"):
            cmds[words[0]] = shlex.split(line)[2:]
    return cmds


def render(binary, args, seed, stem, reuse=False):
    """Renders one case at `seed`; returns the PFM's path."""
    if reuse and os.path.isfile(stem + ".pfm"):
        return stem + ".pfm"
    a = list(args)
    for flag in ("--seed", "-f", "--pfm"):
        i = a.index(flag)
        del a[i : i + 2]
    # The scene stays last: the options go before it.
    a[-1:-1] = ["--seed", str(seed), "-f", stem + ".png", "--pfm", stem + ".pfm", "-t", "1", "--no-progress"]
    r = subprocess.run([binary] + a, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{binary} {' '.join(a)}: exit {r.returncode}: {r.stderr.strip()[-300:]}")
    return stem + ".pfm"


def block_means(w, h, img, size=8):
    """Per block and channel, the mean (blocks that fit whole)."""
    bw, bh = w // size, h // size
    out = [0.0] * (bw * bh * 3)
    for y in range(bh * size):
        row = y * w * 3
        b_row = (y // size) * bw
        for x in range(bw * size):
            k = (b_row + x // size) * 3
            p = row + 3 * x
            out[k] += img[p]
            out[k + 1] += img[p + 1]
            out[k + 2] += img[p + 2]
    n = size * size
    return [v / n for v in out]


def block_sums(w, h, img, size=8):
    return [v * size * size for v in block_means(w, h, img, size)]


def judge_monte_carlo(case, pfms):
    ref_dir = os.path.join(ROOT, "reference_images", case)
    w, h, m = read_pfm(os.path.join(ref_dir, "mean.pfm"))
    _, _, v = read_pfm(os.path.join(ref_dir, "variance.pfm"))
    runs = json.load(open(os.path.join(ref_dir, "meta.json")))["runs"]
    images = []
    for p in pfms:
        pw, ph, img = read_pfm(p)
        if (pw, ph) != (w, h):
            return {"error": f"{p}: {pw}x{ph}, the reference is {w}x{h}"}
        images.append(img)
    n = len(images)
    bad = sum(1 for img in images for x in img if not math.isfinite(x))
    if bad:
        return {"error": f"{bad} NaN or infinite channels over {n} renders"}
    npix = w * h
    res = {"renders": n}
    # Image mean per channel.
    zs, means = [], []
    for c in range(3):
        per_render = [sum(img[c::3]) / npix for img in images]
        mu = sum(per_render) / n
        var = sum((x - mu) ** 2 for x in per_render) / (n - 1)
        ref_mu = sum(m[c::3]) / npix
        ref_var = sum(v[c::3]) / (npix * npix * runs)
        zs.append((mu - ref_mu) / math.sqrt(var / n + ref_var))
        means.append((mu, ref_mu))
    res["mean_z"] = zs
    res["means"] = means
    # Blocks.
    size = 8
    ref_b = block_means(w, h, m, size)
    ref_bv = [s / (size * size) ** 2 / runs for s in block_sums(w, h, v, size)]  # var of the ref's block mean
    per = [block_means(w, h, img, size) for img in images]
    nb = len(ref_b)
    z2, off = 0.0, 0
    alpha = 0.01
    p_each = 1 - (1 - alpha) ** (1 / nb)
    limit = NormalDist().inv_cdf(1 - p_each / 2)
    worst = 0.0
    for k in range(nb):
        xs = [b[k] for b in per]
        mu = sum(xs) / n
        var = sum((x - mu) ** 2 for x in xs) / (n - 1)
        # Plus float round-off (1e-6 of the value): a block that only an
        # edge's anti-aliasing moves varies by less than the PFMs' precision.
        se2 = var / n + ref_bv[k] + (1e-6 * ref_b[k]) ** 2
        if se2 <= 0:
            z = 0.0 if abs(mu - ref_b[k]) <= 1e-6 * (1 + abs(ref_b[k])) else math.inf
        else:
            z = (mu - ref_b[k]) / math.sqrt(se2)
        z2 += z * z
        worst = max(worst, abs(z))
        off += abs(z) > limit
    res.update(blocks=nb, blocks_off=off, block_limit=limit, block_mean_z2=z2 / nb, block_max_z=worst)
    return res


def judge_deterministic(case, pfm):
    w, h, m = read_pfm(os.path.join(ROOT, "reference_images", case, "mean.pfm"))
    pw, ph, c = read_pfm(pfm)
    if (pw, ph) != (w, h):
        return {"error": f"{pfm}: {pw}x{ph}, the reference is {w}x{h}"}
    if any(not math.isfinite(x) for x in c):
        return {"error": "NaN or infinite channels"}
    diffs = [abs(a - b) for a, b in zip(c, m)]
    off = sum(1 for d, b in zip(diffs, m) if d > 1e-3 + 1e-3 * abs(b))
    return {"max_diff": max(diffs), "off_share": off / len(diffs), "identical": max(diffs) == 0.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", action="append", required=True, help="NAME=PATH of a pathtracer")
    ap.add_argument("--case", action="append", required=True)
    ap.add_argument("--renders", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=3000)
    ap.add_argument("-j", type=int, default=2)
    ap.add_argument("--grader", default=os.path.join(ROOT, "build", "bin", "grader"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "legal_variants", "unbiased"))
    ap.add_argument("--json", help="also write every figure to this JSON file")
    ap.add_argument("--paired", action="store_true",
                    help="render every build at --first-seed only and compare each with the first build's image")
    ap.add_argument("--table", help="also write a Markdown summary to this file")
    ap.add_argument("--reuse", action="store_true", help="judge the renders already in --work again (no rendering)")
    a = ap.parse_args()
    if a.renders < 4:
        ap.error("--renders must be at least 4")
    builds = []
    for b in a.build:
        name, sep, path = b.partition("=")
        if not sep or not os.access(path, os.X_OK):
            ap.error(f"--build {b}: want NAME=PATH of an executable")
        builds.append((name, os.path.abspath(path)))
    cmds = case_commands(a.grader)
    for c in a.case:
        if c not in cmds:
            ap.error(f"--case {c}: not a grading case (grader compare --list)")
        if not os.path.isfile(os.path.join(ROOT, "reference_images", c, "meta.json")):
            ap.error(f"--case {c}: no reference in reference_images/{c}")
    if a.paired:
        return paired(builds, cmds, a)
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.j) as pool:
        for name, binary in builds:
            for case in a.case:
                meta = json.load(open(os.path.join(ROOT, "reference_images", case, "meta.json")))
                det = meta.get("deterministic", False)
                d = os.path.join(a.work, name, case)
                os.makedirs(d, exist_ok=True)
                # Each build its own seeds (from its name), so that two builds
                # that draw the same numbers are not judged on the same luck.
                first = a.first_seed + 100 * (zlib.crc32(name.encode()) % 10000)
                seeds = [first] if det else [first + i for i in range(a.renders)]
                futs = [pool.submit(render, binary, cmds[case], s, os.path.join(d, f"s{s}"), a.reuse) for s in seeds]
                try:
                    pfms = [f.result() for f in futs]
                    r = judge_deterministic(case, pfms[0]) if det else judge_monte_carlo(case, pfms)
                except (RuntimeError, ValueError) as e:
                    r = {"error": str(e)}
                r["deterministic"] = det
                results.setdefault(name, {})[case] = r
                print(f"{name:28s} {case:22s} {line(r)}", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)
    if a.table:
        write_table(a.table, results, a)
    return 0


def paired(builds, cmds, a):
    """--paired: every build renders each case at the same seed (--first-seed)
    as the first build; prints how much of each image is bit-identical to
    the first build's. A build whose answers and random numbers are the
    reference's (another BVH, another order of tests) matches it exactly."""
    (first, first_bin), others = builds[0], builds[1:]
    cells = {n: {} for n, _ in others}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.j) as pool:
        for case in a.case:
            d = os.path.join(a.work, "paired", case)
            os.makedirs(d, exist_ok=True)
            futs = {n: pool.submit(render, b, cmds[case], a.first_seed, os.path.join(d, n), a.reuse) for n, b in builds}
            _, _, ref = read_pfm(futs[first].result())
            for n, _ in others:
                try:
                    _, _, img = read_pfm(futs[n].result())
                except (RuntimeError, ValueError) as e:
                    print(f"{n:28s} {case:22s} ERROR: {e}", flush=True)
                    cells[n][case] = "error"
                    continue
                diffs = [abs(x - y) for x, y in zip(img, ref)]
                same = sum(1 for x in diffs if x == 0) / len(diffs)
                bad = sum(1 for x in img if not math.isfinite(x))
                print(f"{n:28s} {case:22s} seed {a.first_seed}: {100 * same:6.2f} % of channels identical to {first}'s, "
                      f"largest difference {max(diffs):.3g}" + (f", {bad} NaN or infinite channels" if bad else ""),
                      flush=True)
                cells[n][case] = ("identical" if same == 1 else f"{100 * same:.2f} %, max {max(diffs):.2g}") + \
                    (" (NaN)" if bad else "")
    if a.table:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                                text=True).stdout.strip() or "unknown"
        out = [f"Made by `instructors/legal_variants/check_unbiased.py --paired --first-seed {a.first_seed}` at commit "
               f"{commit} on {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%dT%H:%M:%SZ}: the share of each "
               f"image's channels bit-identical to {first}'s at the same seed, and the largest difference.", "",
               "| build | " + " | ".join(a.case) + " |", "|---|" + "---|" * len(a.case)]
        for n, _ in others:
            out.append(f"| {n} | " + " | ".join(cells[n].get(c, "") for c in a.case) + " |")
        with open(a.table, "w") as f:
            f.write("\n".join(out) + "\n")
    return 0


def write_table(path, results, a):
    """A Markdown summary: per build, then every Monte Carlo case's image-mean z."""
    builds = list(results)
    cases = [c for c in a.case if not any(results[b][c].get("deterministic") for b in builds)]
    det = [c for c in a.case if c not in cases]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    nb = next((r["blocks"] for b in builds for r in results[b].values() if "blocks" in r), 0)
    out = [f"Made by `instructors/legal_variants/check_unbiased.py --renders {a.renders} --first-seed {a.first_seed}` "
           f"at commit {commit} on {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%dT%H:%M:%SZ}.", "",
           "| build | largest image-mean \|z\| (case) | blocks off, all cases | block mean z² (range over cases) | "
           f"deterministic cases identical ({len(det)}) | errors |",
           "|---|---|---:|---|---|---|"]
    for b in builds:
        mc = [(c, results[b][c]) for c in cases if "error" not in results[b][c]]
        errs = [f"{c}: {results[b][c]['error']}" for c in a.case if "error" in results[b][c]]
        if mc:
            c, r = max(mc, key=lambda cr: max(abs(z) for z in cr[1]["mean_z"]))
            worst = f"{max(r['mean_z'], key=abs):+.2f} ({c})"
            off = sum(r["blocks_off"] for _, r in mc)
            z2 = [r["block_mean_z2"] for _, r in mc]
            z2s = f"{min(z2):.2f}-{max(z2):.2f}"
        else:
            worst, off, z2s = "-", "-", "-"
        ds = [results[b][c] for c in det if "error" not in results[b][c]]
        ident = sum(1 for r in ds if r["identical"])
        dcell = f"{ident}" + ("" if ident == len(ds) else
                              f" (others: max diff {max(r['max_diff'] for r in ds):.1g}, "
                              f"{100 * max(r['off_share'] for r in ds):.2f} % beyond the grader's round-off)")
        out.append(f"| {b} | {worst} | {off} | {z2s} | {dcell} | {'; '.join(errs) or '-'} |")
    out += ["", "Image-mean z per case (the channel of largest |z|; NaN: the renders had NaN or infinite pixels):", "",
            "| build | " + " | ".join(cases) + " |", "|---|" + "---:|" * len(cases)]
    for b in builds:
        cells = []
        for c in cases:
            r = results[b][c]
            cells.append("NaN" if "error" in r else f"{max(r['mean_z'], key=abs):+.2f}")
        out.append(f"| {b} | " + " | ".join(cells) + " |")
    out.append("")
    with open(path, "w") as f:
        f.write("\n".join(out))


def line(r):
    if "error" in r:
        return "ERROR: " + r["error"]
    if r["deterministic"]:
        return (f"deterministic: {'identical' if r['identical'] else 'max |diff| %.2g' % r['max_diff']}, "
                f"{100 * r['off_share']:.3f} % of channels beyond 1e-3 + 1e-3 |m|")
    z = ", ".join(f"{x:+.2f}" for x in r["mean_z"])
    mu = ", ".join(f"{b:.5f}/{ref:.5f}" for b, ref in r["means"])
    return (f"image mean z (r, g, b) {z}; blocks off {r['blocks_off']}/{r['blocks']} (|z| > {r['block_limit']:.2f}), "
            f"mean z^2 {r['block_mean_z2']:.2f}, max |z| {r['block_max_z']:.2f}; means {mu}")


if __name__ == "__main__":
    sys.exit(main())
