"""The BVH figures: `pathtracer --bvh-boxes D` and `--bvh-node N` draw the
render's own BVH boxes over the PNG, and the write-up's `p2_bvh_boxes` set
shows them.

A scene of two triangles far apart (`--bvh-leaf 1`: the root splits into
one leaf per triangle) seen through a camera settings file: the root's box
is the two triangles' bounds, each child's box one triangle's. Their edges
are projected here, independently of the renderer, with the camera file's
pinhole model, and the pixels along each visible edge (away from the
corners) must be the box's colour; pixels far from every edge must be the
render's own (the same as without the flag).
"""

import json
import math
import os
import struct
import subprocess
import tempfile
import zlib

from support import GENERATOR, RECIPES, check, run

# The viewer's BVH-mode colours (view3d.js), as PNG bytes.
YELLOW, WHITE, RED, BLUE = (0xe6, 0xd8, 0x4a), (0xff, 0xff, 0xff), (0xff, 0x4d, 0x4d), (0x4d, 0xa6, 0xff)

# Two triangles: one in x [-2, -1], one in x [1, 2].
TRI_A = [(-2, -1, -1), (-1, -1, -1), (-1.5, 1, -0.5)]
TRI_B = [(1, -1, 0.5), (2, -1, 1), (1.5, 1, 1)]

SCENE = """<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam"><optics><technique_common><perspective>
    <xfov>50</xfov><aspect_ratio>1.333333</aspect_ratio><znear>0.1</znear><zfar>100</zfar>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_geometries><geometry id="tris"><mesh>
    <source id="p"><float_array id="pa" count="18">{coords}</float_array>
      <technique_common><accessor source="#pa" count="6" stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 3 4 5</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene">
    <node id="Camera"><matrix>1 0 0 0 0 1 0 0 0 0 1 8 0 0 0 1</matrix><instance_camera url="#cam"/></node>
    <node id="Tris"><instance_geometry url="#tris"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
"""

W, H = 240, 180
HFOV, VFOV = 60.0, 2 * math.degrees(math.atan(math.tan(math.radians(30)) * 0.75))
EYE, TARGET = (3.0, 2.5, 7.0), (0.0, 0.0, 0.0)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(dot(a, a))
    return tuple(x / n for x in a)


# The camera's axes: it looks along -z, x right, y up.
AZ = unit(sub(EYE, TARGET))
AX = unit(cross((0, 1, 0), AZ))
AY = cross(AZ, AX)


def camera_file(path):
    """The course's six-line camera settings file for EYE, TARGET, HFOV, VFOV."""
    m = [AX[0], AY[0], AZ[0], AX[1], AY[1], AZ[1], AX[2], AY[2], AZ[2]]
    lines = [f"{HFOV} {VFOV} 0 0.01 100", " ".join(map(repr, EYE + TARGET)), "0 0 8 0.01 100",
             " ".join(map(repr, m)), "1 1 0", "4.7 0"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def project(p):
    """World point -> (column, row from the top) in the PNG, as real numbers."""
    d = sub(p, EYE)
    depth = -dot(d, AZ)
    x = (dot(d, AX) / (depth * math.tan(math.radians(HFOV / 2))) + 1) / 2 * W
    y = (dot(d, AY) / (depth * math.tan(math.radians(VFOV / 2))) + 1) / 2 * H
    return x, H - y


def bounds(points):
    return tuple(min(p[k] for p in points) for k in range(3)), tuple(max(p[k] for p in points) for k in range(3))


EDGES = [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5), (2, 6), (3, 7)]


def box_segments(box):
    lo, hi = box
    corner = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    return [(project(corner[a]), project(corner[b])) for a, b in EDGES]


def read_png(path):
    """A non-interlaced PNG of 8 bits or fewer per sample (the encoder picks
    grey, palette, RGB or RGBA by the image's colours) -> (width, height,
    rows of RGB bytes)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, palette = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body[:13])
            assert depth <= 8 and interlace == 0, f"{path}: {depth}-bit or interlaced PNG"
        elif kind == b"PLTE":
            palette = [tuple(body[3 * k:3 * k + 3]) for k in range(n // 3)]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[ctype]
    bpp = max(1, channels * depth // 8)  # the filters' byte distance
    stride = (w * channels * depth + 7) // 8
    raw, rows, prev = zlib.decompress(idat), [], bytearray(stride)
    for r in range(h):
        ft, line = raw[r * (stride + 1)], bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        prev = line
        # Samples, then pixels as RGB.
        if depth == 8:
            samples = list(line)
        else:
            per = 8 // depth
            samples = [(line[k // per] >> (8 - depth * (k % per + 1))) & ((1 << depth) - 1) for k in range(w * channels)]
        out = bytearray()
        for x in range(w):
            px = samples[x * channels:(x + 1) * channels]
            if ctype == 3:
                out += bytes(palette[px[0]])
            elif ctype in (0, 4):
                g = px[0] * 255 // ((1 << depth) - 1)
                out += bytes((g, g, g))
            else:
                out += bytes(px[:3])
        rows.append(bytes(out))
    return w, h, rows


def pixel(img, x, y):
    r = img[2][y]
    return tuple(r[3 * x:3 * x + 3])


def near(img, x, y, color, reach=1):
    """Whether a pixel within `reach` of (x, y) has `color` (or one of a tuple of colours)."""
    w, h, _ = img
    colors = color if isinstance(color[0], tuple) else (color,)
    return any(0 <= x + i < w and 0 <= y + j < h and pixel(img, x + i, y + j) in colors
               for i in range(-reach, reach + 1) for j in range(-reach, reach + 1))


def edge_hits(img, segments, color):
    """Points sampled along the segments' middles (10%..90%), inside the
    image: how many there were and how many have `color` within a pixel."""
    n = hits = 0
    for (x0, y0), (x1, y1) in segments:
        if math.hypot(x1 - x0, y1 - y0) < 8:
            continue  # an edge seen end on
        for k in range(1, 10):
            x, y = x0 + (x1 - x0) * k / 10, y0 + (y1 - y0) * k / 10
            if 2 <= x < W - 2 and 2 <= y < H - 2:
                n += 1
                hits += near(img, int(x), int(y), color)
    return n, hits


def render(pathtracer, tmp, name, extra, must_succeed=True):
    out = os.path.join(tmp, name + ".png")
    r = subprocess.run([pathtracer, "--part", "2", "--bvh-leaf", "1", "-r", str(W), str(H), "-c",
                        os.path.join(tmp, "cam.txt"), "--no-progress", "--stats-json",
                        os.path.join(tmp, name + ".json"), "-f", out] + extra + [os.path.join(tmp, "two.dae")],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if must_succeed:
        check(r.returncode == 0, f"pathtracer {' '.join(extra)} exits 0 (stderr: {r.stderr.strip()})")
    return read_png(out) if r.returncode == 0 else None, r


def test_boxes(a):
    with tempfile.TemporaryDirectory() as tmp:
        coords = " ".join(str(c) for p in TRI_A + TRI_B for c in p)
        with open(os.path.join(tmp, "two.dae"), "w") as f:
            f.write(SCENE.format(coords=coords))
        camera_file(os.path.join(tmp, "cam.txt"))
        plain, _ = render(a.pathtracer, tmp, "plain", [])
        root = bounds(TRI_A + TRI_B)
        depth0, _ = render(a.pathtracer, tmp, "depth0", ["--bvh-boxes", "0"])
        depth1, _ = render(a.pathtracer, tmp, "depth1", ["--bvh-boxes", "1"])
        node0, _ = render(a.pathtracer, tmp, "node0", ["--bvh-node", "0"])
        if not (plain and depth0 and depth1 and node0):
            return
        n, hits = edge_hits(depth0, box_segments(root), YELLOW)
        check(n >= 60 and hits == n, f"--bvh-boxes 0: the root box's projected edges are yellow ({hits} of {n} points)")
        for kid in (TRI_A, TRI_B):
            n, hits = edge_hits(depth1, box_segments(bounds(kid)), YELLOW)
            check(n >= 30 and hits == n, f"--bvh-boxes 1: a child's projected edges are yellow ({hits} of {n} points)")
        # The children are drawn over the node (as in the viewer): where a
        # child's edge lies on the root's, it is red or blue.
        n, white = edge_hits(node0, box_segments(root), WHITE)
        _, any_color = edge_hits(node0, box_segments(root), (WHITE, RED, BLUE))
        check(n >= 60 and any_color == n and white >= 0.3 * n,
              f"--bvh-node 0: the root box's edges are white, or a child's colour where a child's edge covers them "
              f"({white} white, {any_color} of {n} points)")
        # Which child is left is the build's choice: one red, one blue.
        kid_colors = set()
        for kid in (TRI_A, TRI_B):
            for color in (RED, BLUE):
                n, hits = edge_hits(node0, box_segments(bounds(kid)), color)
                if hits >= 0.7 * n:  # the root's white edges are drawn over the children's where they meet
                    kid_colors.add(color)
        check(kid_colors == {RED, BLUE}, f"--bvh-node 0: one child's box red, the other's blue (found {kid_colors})")
        # Away from every edge the pixels are the render's.
        segs = box_segments(root) + box_segments(bounds(TRI_A)) + box_segments(bounds(TRI_B))
        changed = far_changed = 0
        for y in range(H):
            for x in range(W):
                if pixel(node0, x, y) == pixel(plain, x, y):
                    continue
                changed += 1
                d = min(distance_to_segment(x + 0.5, y + 0.5, s) for s in segs)
                far_changed += d > 3
        check(changed > 0 and far_changed == 0,
              f"only pixels on the projected edges change ({changed} changed, {far_changed} of them away from the edges)")
        with open(os.path.join(tmp, "plain.json")) as f:
            plain_stats = json.load(f)
        with open(os.path.join(tmp, "node0.json")) as f:
            node_stats = json.load(f)
        check(plain_stats["max_radiance"] == node_stats["max_radiance"],
              "--stats-json is the render's: the boxes do not change max_radiance")
        # A node the tree does not have: the plain render and a warning
        # (an unfinished part 2 still gets its figure); part 1 has no BVH.
        missing, r = render(a.pathtracer, tmp, "missing", ["--bvh-node", "99"])
        check(r.returncode == 0 and "warning: --bvh-node 99" in r.stderr and missing == plain,
              f"--bvh-node 99 of a 3-node tree draws nothing and warns (exit {r.returncode}, {r.stderr.strip()})")
        r = subprocess.run([a.pathtracer, "--part", "1", "--bvh-boxes", "2", "-f", os.path.join(tmp, "p1.png"),
                            os.path.join(tmp, "two.dae")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        check(r.returncode == 2 and "--part 2" in r.stderr and not os.path.exists(os.path.join(tmp, "p1.png")),
              f"--bvh-boxes with --part 1 is refused before rendering ({r.stderr.strip()})")

        # The write-up's figure set, --quick: made, and each image shows its boxes.
        out = os.path.join(tmp, "page")
        r = run([GENERATOR, "--quick", "--only", "p2_bvh_boxes", "--pathtracer", a.pathtracer, "--out", out,
                 "--no-progress", "--recipes", RECIPES])
        check(r.returncode == 0, f"the p2_bvh_boxes figures are made (exit {r.returncode}: {r.stderr.strip()})")
        with open(os.path.join(out, "manifest.json")) as f:
            manifest = json.load(f)
        figures = [fig for fig in manifest["figures"] if fig.get("grid") == "p2_bvh_boxes"]
        check(len(figures) >= 2, f"the set has its figures ({len(figures)})")
        for fig in figures:
            img = read_png(os.path.join(out, fig["image"]))
            colors = {YELLOW: 0, WHITE: 0, RED: 0, BLUE: 0}
            for y in range(img[1]):
                for x in range(img[0]):
                    p = pixel(img, x, y)
                    if p in colors:
                        colors[p] += 1
            # A --quick image shows the whole view (at the figure's size: the
            # boxes are drawn over the PNG): a node figure shows all three boxes.
            check(img[:2] == (480, 360), f"{fig['image']}: the whole 480 x 360 view (got {img[0]} x {img[1]})")
            wanted = [WHITE, RED, BLUE] if "--bvh-node" in fig["command"] else [YELLOW]
            check(all(colors[c] >= 20 for c in wanted),
                  f"{fig['image']}: shows its boxes ({', '.join(f'{colors[c]} pixels {c}' for c in wanted)})")


def distance_to_segment(x, y, seg):
    (x0, y0), (x1, y1) = seg
    dx, dy = x1 - x0, y1 - y0
    L = dx * dx + dy * dy
    t = 0 if L == 0 else max(0.0, min(1.0, ((x - x0) * dx + (y - y0) * dy) / L))
    return math.hypot(x - x0 - t * dx, y - y0 - t * dy)
