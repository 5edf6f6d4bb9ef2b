#!/usr/bin/python3
"""Writes a narrow fan as a Triangle .poly: WEDGES spikes of WIDTH degrees each around the origin.

The polygon runs from the origin to the outer vertices at radius 1 (angles i * WIDTH, i = 0..WEDGES)
with a vertex at radius INNER between each two of them (angle (i + 1/2) * WIDTH): one closed
boundary, WEDGES needle-like wedges. A bundle-removal stress input (issue 32): every skinny
triangle of its constrained Delaunay triangulation lies in long, nearly parallel circumdisks.

Usage: make_fan_poly.py OUT.poly [WEDGES=1000] [WIDTH_DEG=0.01] [INNER=0.01]
"""
import math
import sys


def main():
    out = sys.argv[1]
    wedges = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    width = float(sys.argv[3]) if len(sys.argv) > 3 else 0.01
    inner = float(sys.argv[4]) if len(sys.argv) > 4 else 0.01
    pts = [(0.0, 0.0)]
    for i in range(wedges + 1):
        a = math.radians(i * width)
        pts.append((math.cos(a), math.sin(a)))
        if i < wedges:
            b = math.radians((i + 0.5) * width)
            pts.append((inner * math.cos(b), inner * math.sin(b)))
    with open(out, "w") as f:
        f.write(f"{len(pts)} 2 0 0\n")
        for i, (x, y) in enumerate(pts):
            f.write(f"{i + 1} {x!r} {y!r}\n")
        f.write(f"{len(pts)} 0\n")
        for i in range(len(pts)):
            f.write(f"{i + 1} {i + 1} {(i + 1) % len(pts) + 1}\n")
        f.write("0\n")


if __name__ == "__main__":
    main()
