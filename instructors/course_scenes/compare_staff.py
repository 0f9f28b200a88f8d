#!/usr/bin/env python3
"""Does our renderer draw a course scene as the course's staff image shows it?

The staff image is one render at an unknown seed, an 8-bit PNG in the
course's conversion (byte = floor(255 (sqrt(2) L)^(1/2.2)), clamped). Ours
are K renders of the same scene with the staff image's settings, at seeds
--first-seed .. --first-seed + K - 1, written by our pathtracer in that same
conversion. Both are compared in the PNG's values (byte / 255), never in
radiance: that is all the staff image has.

The image is cut into a coarse grid (--grid 8 6: 8 columns, 6 rows, edges
rounded to whole pixels). For every block and colour channel, the staff
block mean y is set against our K block means (mean m, spread s, ddof 1) as
one more draw from the same distribution would be:

    t = (y - m) / (s_eff * sqrt(1 + 1/K)),   Student t with K - 1 df,

s_eff = max(s, 1 / (255 sqrt(12 n))) for a block of n pixels (a block that
is black or white in every render of ours has s = 0; the floor is the
8-bit rounding of one image's block mean). Two-sided p values, Holm's
step-down over all blocks x 3 channels at --alpha; the whole-image mean is
tested the same way (3 channels, Holm at --alpha, apart from the blocks).

What the test assumes, and what breaks it:
  - the staff image has our noise. A block mean of gamma-encoded values
    depends on the noise itself (the curve is concave, so a noisier image
    has darker means, and clamping at 255 cuts bright noise): at another
    sample count the staff means are shifted even if both renderers are
    right. Give the staff image's -s/-l/-m; if they are not known, say so,
    and read a flagged block by its size in 8-bit levels, not by its p.
  - the staff PNG is the renderer's own file (not rescaled, not JPEG).
    Its size is the -r of our renders unless -r is given.

  compare_staff.py --scene DAE (--staff PNG | --pseudo-staff SEED)
                   -s N -l N -m N [-r W H] [--extra "FLAGS"] [-K 8]
                   [--grid 8 6] [--alpha 0.05] [--pathtracer PATH]
                   [--work DIR] [--figure PNG] [--markdown FILE --title T]

--pseudo-staff SEED stands our own render at SEED (with --pseudo-staff-args
added to its command; -s/-l/-m N there replace ours, e.g. "-s 16") in for the staff image: the check of
the test itself, and what can be compared when no staff image is at hand.
--figure writes staff | our mean | the blocks' differences (grey = 0, red =
staff brighter, blue = darker, full colour at 4 levels of 255), the flagged
blocks outlined in yellow.
"""
import argparse
import math
import os
import shlex
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


# ---------------------------------------------------------------- PNG files

def read_png(path):
    """8- or 16-bit, non-interlaced PNG -> float array H x W x 3 in [0, 1]."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        sys.exit(f"compare_staff: error: {path}: {e.strerror}")
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"compare_staff: error: {path}: not a PNG file")
    try:
        return decode_png(data, path)
    except (struct.error, zlib.error, ValueError, IndexError, NameError) as e:
        sys.exit(f"compare_staff: error: {path}: damaged PNG ({type(e).__name__}: {e})")


def decode_png(data, path):
    pos, idat, palette = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            width, height, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"PLTE":
            palette = np.frombuffer(body, np.uint8).reshape(-1, 3)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}.get(ctype)
    if channels is None or interlace or depth not in (8, 16) or (ctype == 3 and depth != 8):
        sys.exit(f"compare_staff: error: {path}: PNG of colour type {ctype}, depth {depth}, "
                 f"interlace {interlace} is not read (8/16-bit, non-interlaced only)")
    bpp = channels * depth // 8
    stride = width * bpp
    raw = np.frombuffer(zlib.decompress(b"".join(idat)), np.uint8)
    rows = np.zeros((height, stride), np.int32)
    prev = np.zeros(stride, np.int32)
    for y in range(height):
        line = raw[y * (stride + 1):(y + 1) * (stride + 1)]
        ftype, cur = line[0], line[1:].astype(np.int32)
        if ftype == 1 or ftype == 3 or ftype == 4:
            out = np.zeros(stride, np.int32)
            for x in range(stride):  # depends on the byte just decoded
                a = out[x - bpp] if x >= bpp else 0
                b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
                if ftype == 1:
                    pred = a
                elif ftype == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                out[x] = (cur[x] + pred) & 255
            cur = out
        elif ftype == 2:
            cur = (cur + prev) & 255
        rows[y], prev = cur, cur
    if depth == 16:
        rows = rows[:, 0::2] * 256 + rows[:, 1::2]
    img = rows.reshape(height, width, channels)
    if ctype == 3:
        img = palette[img[:, :, 0]].astype(np.int32)
    elif channels <= 2:
        img = np.repeat(img[:, :, :1], 3, axis=2)
    return img[:, :, :3].astype(np.float64) / (255.0 if depth == 8 else 65535.0)


def write_png(path, rgb):
    """H x W x 3 uint8 -> PNG (filter 0 on every row)."""
    height, width, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(height))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


# ---------------------------------------------------------------- statistics

def t_two_sided_p(t, df):
    """P(|T| >= |t|) for Student's t with integer df (Abramowitz-Stegun 26.7.3-4)."""
    t = abs(t)
    if math.isinf(t):
        return 0.0
    theta = math.atan(t / math.sqrt(df))
    c2 = math.cos(theta) ** 2
    if df % 2 == 1:
        total, term = 0.0, 1.0
        if df > 1:
            total = term = 1.0
            for k in range(1, (df - 3) // 2 + 1):
                term *= c2 * (2 * k) / (2 * k + 1)
                total += term
        a = 2 / math.pi * (theta + (math.sin(theta) * math.cos(theta) * total if df > 1 else 0.0))
    else:
        total = term = 1.0
        for k in range(1, (df - 2) // 2 + 1):
            term *= c2 * (2 * k - 1) / (2 * k)
            total += term
        a = math.sin(theta) * total
    return max(0.0, 1.0 - a)


def holm(pvalues, alpha):
    """Holm's step-down: which hypotheses are rejected at family-wise alpha."""
    order = sorted(range(len(pvalues)), key=lambda i: pvalues[i])
    rejected = [False] * len(pvalues)
    m = len(pvalues)
    for rank, i in enumerate(order):
        if pvalues[i] > alpha / (m - rank):
            break
        rejected[i] = True
    return rejected


def block_edges(n, parts):
    return [round(i * n / parts) for i in range(parts + 1)]


def block_means(img, cols, rows, keep=None):
    """Per block and channel, the mean over the pixels `keep` (H x W bool,
    default all) holds; a block with no such pixel gets 0."""
    xs, ys = block_edges(img.shape[1], cols), block_edges(img.shape[0], rows)
    if keep is None:
        keep = np.ones(img.shape[:2], bool)
    out = np.zeros((rows, cols, 3))
    for r in range(rows):
        for c in range(cols):
            k = keep[ys[r]:ys[r + 1], xs[c]:xs[c + 1]]
            if k.any():
                out[r, c] = img[ys[r]:ys[r + 1], xs[c]:xs[c + 1]][k].mean(axis=0)
    return out, xs, ys


def kept_pixels(shape, rects):
    """H x W bool: False inside each (x, y, w, h) rectangle, y from the top."""
    keep = np.ones(shape[:2], bool)
    for x, y, w, h in rects:
        keep[max(y, 0):max(y + h, 0), max(x, 0):max(x + w, 0)] = False
    return keep


def compare(staff, ours, cols, rows, alpha, keep=None):
    """staff: H x W x 3; ours: K x H x W x 3; keep: the pixels compared (H x
    W bool, default all). Returns the figures as a dict. A block without a
    kept pixel is not tested (p = 1)."""
    k = ours.shape[0]
    if keep is None:
        keep = np.ones(staff.shape[:2], bool)
    y, xs, ys = block_means(staff, cols, rows, keep)
    per = np.array([block_means(o, cols, rows, keep)[0] for o in ours])  # K x rows x cols x 3
    m, s = per.mean(axis=0), per.std(axis=0, ddof=1)
    npix = np.array([[keep[ys[r]:ys[r + 1], xs[c]:xs[c + 1]].sum() for c in range(cols)] for r in range(rows)])
    floor = 1.0 / (255.0 * np.sqrt(12.0 * np.maximum(npix, 1)))[:, :, None]
    s_eff = np.maximum(s, floor)
    t = np.where(npix[:, :, None] > 0, (y - m) / (s_eff * math.sqrt(1 + 1 / k)), 0.0)
    p = np.vectorize(lambda v: t_two_sided_p(v, k - 1))(t)
    rejected = np.array(holm(list(p.ravel()), alpha)).reshape(p.shape)
    # Whole image, per channel.
    wy, wm_all = staff[keep].mean(axis=0), ours[:, keep].mean(axis=1)
    wm, ws = wm_all.mean(axis=0), wm_all.std(axis=0, ddof=1)
    ws_eff = np.maximum(ws, 1.0 / (255.0 * math.sqrt(12.0 * keep.sum())))
    wt = (wy - wm) / (ws_eff * math.sqrt(1 + 1 / k))
    wp = [t_two_sided_p(v, k - 1) for v in wt]
    return dict(k=k, y=y, m=m, s=s, t=t, p=p, rejected=rejected, xs=xs, ys=ys,
                whole_staff=wy, whole_ours=wm, whole_sd=ws, whole_t=wt, whole_p=wp,
                whole_rejected=holm(wp, alpha))


# ---------------------------------------------------------------- rendering

def render(args, seed, out_png, extra_args=()):
    """Our render at seed; in extra_args, -s/-l/-m N replace the settings, the rest is appended."""
    settings, rest, extra_args = {"-s": args.s, "-l": args.l, "-m": args.m}, [], list(extra_args)
    while extra_args:
        flag = extra_args.pop(0)
        if flag in settings and extra_args:
            settings[flag] = extra_args.pop(0)
        else:
            rest.append(flag)
    cmd = [args.pathtracer, "--part", "9", "-t", str(args.threads), "-s", str(settings["-s"]),
           "-l", str(settings["-l"]), "-m", str(settings["-m"]), "-r", str(args.r[0]), str(args.r[1]),
           "--seed", str(seed), "--no-progress", *shlex.split(args.extra), *rest,
           "-f", out_png, args.scene]
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"compare_staff: error: render failed ({' '.join(map(shlex.quote, cmd))}):\n{done.stderr}")
    return cmd


def figure(path, staff, mean, res):
    """staff | our mean | each block filled by staff - ours (mean of R, G, B):
    grey 0, red staff brighter, blue darker, full at 4 levels of 255."""
    dimg = np.zeros_like(staff)
    rows, cols = res["rejected"].shape[:2]
    for r in range(rows):
        for c in range(cols):
            d = float(np.clip(255 * (res["y"][r, c] - res["m"][r, c]).mean() / 4, -1, 1)) * 0.5
            dimg[res["ys"][r]:res["ys"][r + 1], res["xs"][c]:res["xs"][c + 1]] = (0.5 + d, 0.5 - abs(d), 0.5 - d)
    for r in range(rows):
        for c in range(cols):
            if res["rejected"][r, c].any():
                x0, x1, y0, y1 = res["xs"][c], res["xs"][c + 1] - 1, res["ys"][r], res["ys"][r + 1] - 1
                dimg[y0:y0 + 2, x0:x1 + 1] = dimg[y1 - 1:y1 + 1, x0:x1 + 1] = (1, 1, 0)
                dimg[y0:y1 + 1, x0:x0 + 2] = dimg[y0:y1 + 1, x1 - 1:x1 + 1] = (1, 1, 0)
    gap = np.ones((staff.shape[0], 4, 3))
    both = np.concatenate([staff, gap, mean, gap, dimg], axis=1)
    write_png(path, np.round(np.clip(both, 0, 1) * 255).astype(np.uint8))


# ---------------------------------------------------------------- report

def table(args, res, staff_label, cmd):
    rows, cols = res["rejected"].shape[:2]
    n_cmp = rows * cols * 3
    flagged = [(r, c) for r in range(rows) for c in range(cols) if res["rejected"][r, c].any()]
    ratio = res["whole_staff"].mean() / max(res["whole_ours"].mean(), 1e-12)
    out = [f"### {args.title}", "",
           f"- staff image: {staff_label}",
           f"- our renders: K = {res['k']}, seeds {args.first_seed}..{args.first_seed + res['k'] - 1}; "
           f"the first one's command: `{shown(cmd)}`",
           f"- grid {cols} x {rows} blocks x 3 channels = {n_cmp} comparisons, Holm at alpha = {args.alpha}; "
           f"t with {res['k'] - 1} df",
           f"- blocks that differ (any channel): **{len(flagged)} of {rows * cols}**"
           + (f" ({res['excluded']} pixels left out of both images)" if res.get("excluded") else ""),
           f"- whole-image mean (R, G, B, of byte/255): staff {fmt3(res['whole_staff'])}, ours "
           f"{fmt3(res['whole_ours'])} (render-to-render sd {fmt3(res['whole_sd'], 4)}); "
           f"ratio staff/ours {ratio:.4f}; t {fmt3(res['whole_t'], 2)}; differs (Holm, 3 channels): "
           f"{'yes' if any(res['whole_rejected']) else 'no'}",
           f"- largest block |t|: {np.abs(res['t']).max():.2f}; mean t^2 over the {n_cmp} block-channels: "
           f"{float((res['t'] ** 2).mean()):.2f} (about {(res['k'] - 1) / (res['k'] - 3):.2f} expected if nothing differs)", ""]
    if flagged:
        out += ["| block (col, row from top) | channel | staff | ours (mean ± sd) | staff − ours, 8-bit levels | t | Holm |",
                "|---|---|---|---|---|---|---|"]
        for r, c in flagged:
            for ch in range(3):
                if res["rejected"][r, c, ch]:
                    out.append(f"| ({c}, {r}) | {'RGB'[ch]} | {res['y'][r, c, ch]:.4f} | "
                               f"{res['m'][r, c, ch]:.4f} ± {res['s'][r, c, ch]:.4f} | "
                               f"{255 * (res['y'][r, c, ch] - res['m'][r, c, ch]):+.2f} | {res['t'][r, c, ch]:+.1f} | differs |")
        out.append("")
    return "\n".join(out)


def shown(cmd):
    """The command as run from the project's root, the output under WORK/."""
    out = []
    for prev, a in zip([""] + cmd[:-1], cmd):
        if prev == "-f":
            a = "WORK/" + os.path.basename(a)
        elif os.path.isabs(a) and os.path.exists(a):
            a = os.path.relpath(a, ROOT)
        out.append(shlex.quote(a))
    return " ".join(out)


def fmt3(v, d=4):
    return "(" + ", ".join(f"{x:.{d}f}" for x in v) + ")"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", required=True)
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--staff", help="the staff PNG")
    src.add_argument("--pseudo-staff", type=int, metavar="SEED", help="our own render at SEED stands in")
    ap.add_argument("--pseudo-staff-args", default="",
                    help='flags for the stand-in render, in the = form: --pseudo-staff-args="-s 16"')
    ap.add_argument("-s", type=int, required=True)
    ap.add_argument("-l", type=int, required=True)
    ap.add_argument("-m", type=int, required=True)
    ap.add_argument("-r", type=int, nargs=2, metavar=("W", "H"))
    ap.add_argument("--extra", default="", help='more pathtracer flags for every render, in the = form: --extra="-b 0.1 -d 4"')
    ap.add_argument("-K", type=int, default=8, help="our renders (at least 4)")
    ap.add_argument("--first-seed", type=int, default=1000)
    ap.add_argument("--grid", type=int, nargs=2, default=[8, 6], metavar=("COLS", "ROWS"))
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("-t", "--threads", type=int, default=1)
    ap.add_argument("--pathtracer", default=os.path.join(ROOT, "build", "bin", "pathtracer"))
    ap.add_argument("--work", help="keep the renders here (default: a temporary folder)")
    ap.add_argument("--exclude", type=int, nargs=4, action="append", default=[], metavar=("X", "Y", "W", "H"),
                    help="leave out this rectangle of pixels (y from the top) in both images; repeatable")
    ap.add_argument("--course-watermark", action="store_true",
                    help="leave out the 48 x 5 pixels at the bottom left that some course starters stamp "
                         "into every render")
    ap.add_argument("--figure", help="write staff | our mean | difference here")
    ap.add_argument("--markdown", help="append the result to this file")
    ap.add_argument("--title", default="comparison")
    args = ap.parse_args()
    if args.K < 4:
        sys.exit("compare_staff: error: -K: at least 4 renders (the spread needs them)")
    work = args.work or tempfile.mkdtemp(prefix="compare_staff.")
    os.makedirs(work, exist_ok=True)
    staff = None
    if args.staff:
        staff = read_png(args.staff)
        if args.r is None:
            args.r = [staff.shape[1], staff.shape[0]]
        elif (staff.shape[1], staff.shape[0]) != tuple(args.r):
            sys.exit(f"compare_staff: error: {args.staff}: {staff.shape[1]}x{staff.shape[0]}, not -r {args.r[0]} {args.r[1]}")
        label = f"`{os.path.basename(args.staff)}`, {staff.shape[1]}x{staff.shape[0]}"
    elif args.r is None:
        sys.exit("compare_staff: error: -r is needed with --pseudo-staff")
    ours, first_cmd = [], None
    for i in range(args.K):
        png = os.path.join(work, f"ours_{args.first_seed + i}.png")
        cmd = render(args, args.first_seed + i, png)
        first_cmd = first_cmd or cmd
        ours.append(read_png(png))
        print(f"compare_staff: render {i + 1}/{args.K} done", file=sys.stderr)
    if staff is None:
        png = os.path.join(work, f"pseudo_staff_{args.pseudo_staff}.png")
        render(args, args.pseudo_staff, png, shlex.split(args.pseudo_staff_args))
        staff = read_png(png)
        label = (f"our own render at seed {args.pseudo_staff}"
                 + (f" with `{args.pseudo_staff_args}`" if args.pseudo_staff_args else "") + " (a stand-in)")
    ours = np.array(ours)
    rects = list(args.exclude) + ([[0, staff.shape[0] - 5, 48, 5]] if args.course_watermark else [])
    keep = kept_pixels(staff.shape, rects)
    if not keep.any():
        sys.exit("compare_staff: error: --exclude leaves no pixel to compare")
    res = compare(staff, ours, args.grid[0], args.grid[1], args.alpha, keep)
    res["excluded"] = int((~keep).sum())
    text = table(args, res, label, first_cmd)
    if args.figure:
        figure(args.figure, staff, ours.mean(axis=0), res)
    if args.markdown:
        with open(args.markdown, "a") as f:
            f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
