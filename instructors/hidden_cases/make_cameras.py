#!/usr/bin/env python3
"""Writes the hidden cases' camera settings files (the course's -c format).

Each view looks from an eye point at a target with +y up (the world after
the loader turns a Z_UP file's axes), at the Cornell box scenes' field of
view (49.13 degrees across, 4:3). Run it from any
folder; the files go beside this script:

    instructors/hidden_cases/make_cameras.py
"""
import math
import os

HFOV = 49.13434
ASPECT = 4.0 / 3.0

# name: (eye, target, focal distance), in the world (y up): the box stands
# about 4.5 in front of the eye (along -z), its middle near y = 0.75.
VIEWS = {
    "cb_turned.cam": ((1.3, 1.05, 4.4), (0.0, 0.75, 0.0), 4.6),
    "cb_left_low.cam": ((-0.9, 0.35, 4.5), (0.05, 0.8, 0.0), 4.6),
    "cb_close.cam": ((0.2, 0.85, 3.3), (0.0, 0.7, 0.0), 3.3),
}


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def norm(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def settings(eye, target, focal):
    back = norm(sub(eye, target))          # the camera looks along -z
    right = norm(cross((0.0, 1.0, 0.0), back))
    up = cross(back, right)
    vfov = math.degrees(2 * math.atan(math.tan(math.radians(HFOV) / 2) / ASPECT))
    r = math.sqrt(sum(x * x for x in sub(eye, target)))
    phi = math.degrees(math.atan2(back[0], back[2]))
    theta = math.degrees(math.acos(back[1]))
    # Row-major camera-to-world: the columns are right, up and back.
    c2w = [right[0], up[0], back[0], right[1], up[1], back[1], right[2], up[2], back[2]]
    rows = [
        [HFOV, vfov, ASPECT, 0.1, 100],
        list(eye) + list(target),
        [phi, theta, r, 0.5, 20],
        c2w,
        [0, 0, 0],
        [focal, 0],
    ]
    return "".join(" ".join("%.6f" % v for v in row) + "\n" for row in rows)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    for name, (eye, target, focal) in VIEWS.items():
        with open(os.path.join(here, name), "w") as f:
            f.write(settings(eye, target, focal))
        print("wrote", name)


if __name__ == "__main__":
    main()
