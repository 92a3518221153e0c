#!/usr/bin/env python3
"""exact.py — the exact frame buffers of the textbook's 32x32 examples.

The seed (Russian translation of Rogers, "Procedural Elements for Computer
Graphics", ch. 4) states the examples' polygons and conventions but its 32x32
frame-buffer arrays did not survive (they were pictures).  This script computes
what those arrays must be under the book's own stated conventions, in exact
rational arithmetic:

* pixel (x, y) counts from the bottom-left (seed line 62); it is decided at its
  centre (x + 1/2, y + 1/2) (the half-interval convention, seed lines 70, 148);
* a pixel is covered when its centre is inside the polygon OR ON ITS BOUNDARY
  (seed line 70: "x1 <= x <= x2");
* depth z from the polygon's plane (Newell's method), larger z is nearer
  (observer at +infinity on z); polygons are taken in the book's order and a
  later one replaces an earlier one only if strictly nearer (seed line 32:
  "if z(x, y) > Z_buffer(x, y)"), so an exact tie keeps the earlier polygon.

Usage: python3 exact.py NAME   (NAME: zbuffer, rectangle, warnock) prints the
data file; `python3 exact.py NAME --notes` lists the pixels whose centre is
on a polygon's boundary or whose nearest depth is a tie.
"""
import sys
from fractions import Fraction as F

SCENES = {
    # Example 4.19 (z-buffer), 4.22 (scan-line z-buffer), 4.23 (spans): seed line 58
    "zbuffer": [[(10, 5, 10), (10, 25, 10), (25, 25, 10), (25, 5, 10)],
                [(15, 15, 15), (25, 25, 5), (30, 10, 5)]],
    # Example 4.19, the frame buffer after the rectangle alone (seed line 60)
    "rectangle": [[(10, 5, 10), (10, 25, 10), (25, 25, 10), (25, 5, 10)]],
    # Example 4.17 (Warnock), seed lines 661-663, with polygon 2's last vertex
    # (27, 12, 20) read as (27, 12, 10): the text says polygon 2 lies in z = 10
    "warnock": [[(10, 3, 20), (20, 28, 20), (22, 28, 20), (22, 3, 20)],
                [(5, 12, 10), (5, 20, 10), (27, 20, 10), (27, 12, 10)],
                [(15, 15, 25), (25, 25, 5), (30, 10, 5)]],
}


def plane(p):
    """Newell's plane (a, b, c, d) of polygon p, integers."""
    a = b = c = 0
    for i, (x1, y1, z1) in enumerate(p):
        x2, y2, z2 = p[(i + 1) % len(p)]
        a += (y1 - y2) * (z1 + z2)
        b += (z1 - z2) * (x1 + x2)
        c += (x1 - x2) * (y1 + y2)
    return a, b, c, -(a * p[0][0] + b * p[0][1] + c * p[0][2])


def where(p, x, y):
    """2 inside, 1 on the boundary, 0 outside (p convex)."""
    s = []
    for i, (x1, y1, _) in enumerate(p):
        x2, y2, _ = p[(i + 1) % len(p)]
        s.append((x2 - x1) * (y - y1) - (y2 - y1) * (x - x1))
    if all(v >= 0 for v in s) or all(v <= 0 for v in s):
        return 1 if 0 in s else 2
    return 0


def pixel(scene, x, y):
    cx, cy = F(2 * x + 1, 2), F(2 * y + 1, 2)
    best, bz, cover = 0, None, []
    for i, p in enumerate(scene):
        k = where(p, cx, cy)
        if k:
            a, b, c, d = plane(p)
            z = F(-(a * cx + b * cy + d), c)
            cover.append((i + 1, k, z))
            if bz is None or z > bz:
                best, bz = i + 1, z
    return best, cover


def main():
    name = sys.argv[1]
    scene = SCENES[name]
    for y in range(31, -1, -1):
        row = ""
        for x in range(32):
            v, cover = pixel(scene, x, y)
            row += str(v)
            if "--notes" in sys.argv:
                zs = sorted(z for _, _, z in cover)
                tie = len(zs) > 1 and zs[-1] == zs[-2]
                if tie or any(k == 1 for _, k, _ in cover):
                    print(f"({x},{y}) value {v}{' tie' if tie else ''}: " +
                          ", ".join(f"polygon {i} {'inside' if k == 2 else 'on edge'} z={z}"
                                    for i, k, z in cover))
        if "--notes" not in sys.argv:
            print(row)


if __name__ == "__main__":
    main()
