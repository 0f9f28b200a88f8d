#!/usr/bin/env python3
"""Both renderers against an exact answer: the integrating sphere.

Inside a closed diffuse sphere every patch sends the same share of what it
reflects to every other patch (the form factor dA / A), so light reflected
once or more is uniform: a light of flux Phi inside a sphere of area A and
albedo rho gives each pixel that sees the wall rho^k Phi / (pi A) by the
paths of k bounces. With -m 5, bounces 2 to 5 sum to

    sum_{k=2..5} rho^k Phi / (pi A).

The scene: an icosphere (--level 6: 81,920 triangles, radius 1, facing
inward, albedo 0.5), a one-sided 0.1 x 0.1 area light of radiance 10 at the
centre facing down, the camera inside looking at the upper wall, which the
light does not reach directly. A is the mesh's own area.

Ours renders with --indirect-only; Cycles (cycles_scene.py) at -m 5 minus
-m 1. Each is printed as its ratio to the exact value, with its standard
error over the K renders.

  integrating_sphere.py [--level 6] [-s 256] [-K 8] [--cycles-samples 512]
                        [--size 64 48] [--work DIR]

Needs build/bin/pathtracer and build/bin/scene_json, and Blender (Debian's
blender) for the Cycles half (--no-cycles skips it). About 2 minutes.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from compare_cycles import read_pfm, run  # noqa: E402

ALBEDO, RADIANCE, LIGHT_SIDE = 0.5, 10.0, 0.1
HFOV = 40.0


def icosphere(level):
    """Unit icosphere: (vertices, triangles) wound to face inward."""
    g = (1 + 5 ** 0.5) / 2
    v = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
         (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        middle, finer = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = v[a] + v[b]
                v.append(m / np.linalg.norm(m))
                middle[key] = len(v) - 1
            return middle[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = finer
    return np.array(v), np.array([(a, c, b) for a, b, c in f])


def write_scene(path, verts, tris):
    """The sphere, its material and the light, in the project's own box file
    (scenes/CBspheres_lambertian.dae) with everything else taken out."""
    t = open(os.path.join(ROOT, "scenes", "CBspheres_lambertian.dae")).read()
    pos = " ".join("%.9g" % x for x in verts.ravel())
    geo = ('<geometry id="floor-mesh" name="floor"><mesh>'
           '<source id="floor-mesh-positions"><float_array id="floor-mesh-positions-array" count="%d">%s</float_array>'
           '<technique_common><accessor source="#floor-mesh-positions-array" count="%d" stride="3">'
           '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
           '</accessor></technique_common></source>'
           '<vertices id="floor-mesh-vertices"><input semantic="POSITION" source="#floor-mesh-positions"/></vertices>'
           '<triangles material="floor-material" count="%d">'
           '<input semantic="VERTEX" source="#floor-mesh-vertices" offset="0"/><p>%s</p></triangles>'
           '</mesh></geometry>\n' % (verts.size, pos, len(verts), len(tris), " ".join(map(str, tris.ravel()))))
    a, b = t.index('<geometry id="floor-mesh"'), t.index("</library_geometries>")
    t = t[:a] + geo + t[b:]
    # The light: the box's unit area light scaled to 0.1 x 0.1 at the origin
    # (Z up in the file: it faces down).
    scene = ('<visual_scene id="Scene" name="Scene">'
             '<node id="AreaLight" name="AreaLight" type="NODE"><matrix sid="transform">'
             '%g 0 0 0 0 %g 0 0 0 0 1 0 0 0 0 1</matrix><instance_light url="#AreaLight-light"/></node>'
             '<node id="floor" name="floor" type="NODE"><matrix sid="transform">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1'
             '</matrix><instance_geometry url="#floor-mesh"><bind_material><technique_common>'
             '<instance_material symbol="floor-material" target="#floor-material"/>'
             '</technique_common></bind_material></instance_geometry></node>\n' % (LIGHT_SIDE, LIGHT_SIDE))
    a, b = t.index("<visual_scene"), t.index("</visual_scene>")
    t = t[:a] + scene + t[b:]
    a = t.index('<effect id="floor-effect">')
    b = t.index("</effect>", a)
    effect, n = re.subn(r'<color sid="diffuse">[^<]*</color>',
                        '<color sid="diffuse">%g %g %g 1</color>' % ((ALBEDO,) * 3), t[a:b])
    if n != 1:
        raise SystemExit("integrating_sphere.py: the box file's floor material has changed; update write_scene")
    open(path, "w").write(t[:a] + effect + t[b:])


def camera(w, h):
    """At (0, 0.3, 0) looking along -z with square pixels: it sees the wall
    above the light's plane only."""
    vfov = 2 * math.degrees(math.atan(math.tan(math.radians(HFOV / 2)) * h / w))
    return vfov, ("%g %g %g 0.01 100\n0 0.3 0 0 0.3 -1\n0 0 0 0 0\n1 0 0 0 1 0 0 0 1\n%d %d 0\n1 0\n"
                  % (HFOV, vfov, w / h, w, h))


def mean_and_error(values, exact):
    v = np.array(values) / exact
    return v.mean(), v.std(ddof=1) / math.sqrt(len(v))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--level", type=int, default=6, help="icosphere subdivisions (6: 81,920 triangles)")
    ap.add_argument("-s", type=int, default=256, help="our samples per pixel")
    ap.add_argument("--cycles-samples", type=int, default=512)
    ap.add_argument("-K", type=int, default=8, help="renders by each renderer")
    ap.add_argument("--size", type=int, nargs=2, default=(64, 48), metavar=("W", "H"))
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--work", help="keep the scene and renders here")
    args = ap.parse_args()
    if not 0 <= args.level <= 7 or args.K < 2 or args.s < 1 or args.cycles_samples < 1:
        raise SystemExit("integrating_sphere.py: --level 0..7, -K 2 or more, samples 1 or more")
    w, h = args.size
    work = args.work or tempfile.mkdtemp(prefix="integrating_sphere.")
    os.makedirs(work, exist_ok=True)

    verts, tris = icosphere(args.level)
    p = verts[tris]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
    flux = math.pi * RADIANCE * LIGHT_SIDE ** 2
    exact = sum(ALBEDO ** k * flux / (math.pi * area) for k in range(2, 6))
    dae, cam = os.path.join(work, "isphere.dae"), os.path.join(work, "camera.txt")
    write_scene(dae, verts, tris)
    vfov, text = camera(w, h)
    open(cam, "w").write(text)
    print("icosphere of %d triangles, area %.6f; exact indirect radiance at -m 5: %.7g" % (len(tris), area, exact))

    ours = []
    for k in range(args.K):
        pfm = os.path.join(work, "ours_%d.pfm" % k)
        run([os.path.join(ROOT, "build", "bin", "pathtracer"), "-t", "2", "-s", str(args.s), "-l", "1", "-m", "5",
             "--indirect-only", "-r", str(w), str(h), "-c", cam, "--seed", str(1000 + k), "--no-progress",
             "-f", os.path.join(work, "ours.png"), "--pfm", pfm, dae], "our render")
        ours.append(read_pfm(pfm).mean())
    m, e = mean_and_error(ours, exact)
    print("ours, --indirect-only -m 5, %d x %d spp: %.5f +- %.5f of the exact value" % (args.K, args.s, m, e))
    if args.no_cycles:
        return

    js = os.path.join(work, "isphere.json")
    run([os.path.join(ROOT, "build", "bin", "scene_json"), dae, str(w), str(h), js], "scene_json")
    scene = json.load(open(js))
    scene["camera"].update(position=[0, 0.3, 0], axis_x=[1, 0, 0], axis_y=[0, 1, 0], axis_z=[0, 0, 1],
                           hfov_deg=HFOV, vfov_deg=vfov, lens_radius=0)
    json.dump(scene, open(js, "w"))
    cyc = []
    for k in range(args.K):
        means = []
        for m_ in (1, 5):
            pfm = os.path.join(work, "cycles_m%d_%d.pfm" % (m_, k))
            run(["blender", "-b", "--factory-startup", "-noaudio", "--python", os.path.join(HERE, "cycles_scene.py"),
                 "--", js, pfm, "--samples", str(args.cycles_samples), "--max-depth", str(m_), "--seed", str(k),
                 "--threads", "2"], "Cycles")
            means.append(read_pfm(pfm).mean())
        cyc.append(means[1] - means[0])
    m, e = mean_and_error(cyc, exact)
    print("Cycles, -m 5 minus -m 1, %d x %d spp: %.5f +- %.5f of the exact value" % (args.K, args.cycles_samples, m, e))


if __name__ == "__main__":
    main()
