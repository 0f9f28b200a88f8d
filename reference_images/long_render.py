#!/usr/bin/env python3
"""A long render of one grading case, summarised for the convergence test.

A reference (grader make-references) is the mean of B renders at the case's
own settings. Where the image's light is found by rare paths (a near-mirror
metal lit by light sampling: a light sample lands in its narrow lobe once in
thousands), the mean of B renders sits low most of the time, and their
sample variance, which has not seen the rare paths either, does not say so.
This script renders the case K more times with a lower-variance estimator of
the same expectation (-l multiplied: more light samples at every vertex, the
same expected image) at seeds no reference or candidate uses, and writes per
channel the image mean and each 8 x 8 block's mean (the grader's blocks,
from the top-left corner), with their standard errors from the K renders'
spread, into reference_images/long_renders.json. The test
reference_converged compares every reference with its summary.

  reference_images/long_render.py CASE [--light-factor N] [--renders K] [-j J]
      [--pathtracer build/bin/pathtracer] [--first-seed S]

Run it on purpose (minutes per case); it prints the time it took.
"""
import argparse, json, math, os, shlex, struct, subprocess, sys, tempfile, time
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = 8


def read_pfm(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip()
        if kind != b'PF':
            sys.exit(f'{path}: not a colour PFM')
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    fmt = ('<' if scale < 0 else '>') + 'f' * (w * h * 3)
    vals = struct.unpack(fmt, data[:w * h * 12])
    return w, h, vals  # rows from the bottom


def summarise(w, h, vals):
    """Image mean per channel and block means (top-left first, row by row)."""
    bx, by = (w + BLOCK - 1) // BLOCK, (h + BLOCK - 1) // BLOCK
    blocks = [[0.0, 0.0, 0.0] for _ in range(bx * by)]
    counts = [0] * (bx * by)
    total = [0.0, 0.0, 0.0]
    for yf in range(h):
        yt = h - 1 - yf  # from the top
        for x in range(w):
            b = (yt // BLOCK) * bx + x // BLOCK
            counts[b] += 1
            for c in range(3):
                v = vals[3 * (yf * w + x) + c]
                total[c] += v
                blocks[b][c] += v
    mean = [t / (w * h) for t in total]
    blocks = [[v / counts[i] for v in blk] for i, blk in enumerate(blocks)]
    return mean, blocks, bx, by


def case_line(name):
    with open(os.path.join(ROOT, 'grader', 'cases.txt')) as f:
        for line in f:
            fields = line.split()
            if fields and not fields[0].startswith('#') and fields[0] == name:
                return fields
    sys.exit(f'grader/cases.txt: no case {name}')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('case')
    ap.add_argument('--light-factor', type=int, default=64, help='-l times this (default 64)')
    ap.add_argument('--renders', type=int, default=16)
    ap.add_argument('--first-seed', type=int, default=3000000)
    ap.add_argument('-j', type=int, default=2)
    ap.add_argument('--pathtracer', default=os.path.join(ROOT, 'build', 'bin', 'pathtracer'))
    a = ap.parse_args()
    f = case_line(a.case)
    part, scene, opts = f[1], f[5], f[6:]
    if '-l' not in opts:
        sys.exit(f'{a.case}: the case has no -l to multiply')
    i = opts.index('-l')
    opts = opts[:i + 1] + [str(int(opts[i + 1]) * a.light_factor)] + opts[i + 2:]
    for flag in ('-e', '-c'):
        if flag in opts:
            k = opts.index(flag)
            opts[k + 1] = os.path.join(ROOT, 'scenes', opts[k + 1])
    t0 = time.time()
    tmp = tempfile.mkdtemp(prefix='long_render_')

    def render(k):
        out = os.path.join(tmp, f'r{k}')
        cmd = [a.pathtracer, '--part', part] + opts + ['-t', '1', '--seed', str(a.first_seed + k), '--no-progress',
               '-f', out + '.png', '--pfm', out + '.pfm', os.path.join(ROOT, 'scenes', scene)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        w, h, vals = read_pfm(out + '.pfm')
        os.remove(out + '.pfm'); os.remove(out + '.png')
        for extra in (out + '_rate.png',):
            if os.path.exists(extra):
                os.remove(extra)
        return (w, h) + summarise(w, h, vals)

    with ThreadPoolExecutor(a.j) as pool:
        runs = list(pool.map(render, range(a.renders)))
    os.rmdir(tmp)
    K = len(runs)
    w, h, _, _, bx, by = runs[0]

    def mean_se(values):
        m = sum(values) / K
        var = sum((v - m) ** 2 for v in values) / (K - 1)
        return m, math.sqrt(var / K)

    mean, mean_se_ = zip(*[mean_se([r[2][c] for r in runs]) for c in range(3)])
    blocks, blocks_se = [], []
    for b in range(bx * by):
        ms = [mean_se([r[3][b][c] for r in runs]) for c in range(3)]
        blocks.append([round(m, 9) for m, _ in ms])
        blocks_se.append([round(s, 9) for _, s in ms])
    path = os.path.join(ROOT, 'reference_images', 'long_renders.json')
    data = {'about': 'Long renders of grading cases (reference_images/long_render.py): per channel the image mean and '
                     'each 8 x 8 block mean (from the top-left, row by row), with standard errors from the renders\' '
                     'spread. The test reference_converged holds each reference to them.', 'cases': {}}
    if os.path.exists(path):
        with open(path) as fh:
            data = json.load(fh)
    commit = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'], capture_output=True,
                            text=True).stdout.strip()
    data['cases'][a.case] = {
        'command': 'pathtracer --part ' + part + ' ' +
                   ' '.join(opts).replace(ROOT + '/scenes/', '') + ' ' + scene,
        'light_factor': a.light_factor, 'renders': K, 'first_seed': a.first_seed, 'commit': commit,
        'date': time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime()), 'seconds': round(time.time() - t0, 1),
        'width': w, 'height': h, 'block': BLOCK,
        'mean': [round(m, 9) for m in mean], 'mean_se': [round(s, 9) for s in mean_se_],
        'blocks': blocks, 'blocks_se': blocks_se}
    with open(path + '.tmp', 'w') as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.write('\n')
    os.replace(path + '.tmp', path)
    print(f'{a.case}: {K} renders at -l x{a.light_factor}, {time.time() - t0:.0f} s; image mean '
          + ' '.join(f'{m:.5f}+-{s:.5f}' for m, s in zip(mean, mean_se_)))


if __name__ == '__main__':
    main()
