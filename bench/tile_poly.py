#!/usr/bin/python3
"""Tile a Triangle .poly into a K x K grid of disjoint translated copies (issue 32: opt at scale).

usage: tile_poly.py INPUT.poly COPIES OUTPUT.poly

COPIES must be a perfect square. Copy (i, j) is translated by (i * step_x, j * step_y), where a
step is the bounding box's extent plus a gap of a quarter of it, rounded up to a power of two so
that translating keeps every coordinate exact when the input's are on a coarse enough grid.
The copies are independent, so a weight optimiser's result should weigh COPIES times one copy's.

Measured (2 cores, shared and loaded: wall times are 1.1-2.5x the CPU times), data/Texas.poly,
`mwst triangulate T.poly --method opt` (pieces searched independently, issue 32):
  default options:  1 copy 30,282.27 (8.4 s CPU); 64 copies 1,938,289.2 = 64 x 1 copy + 0.012 %
                    (612 s CPU)
  --opt-trials 0:   1 copy 30,532.50 (0.82 s CPU); 64 copies -0.005 % (51.5 s CPU);
                    1,024 copies 31,258,678.9 = -0.021 % (861 s CPU, 412 MB), both threads equally busy
(Translating rounds the coordinates, so a copy is searched from slightly different points.)
"""
import math
import sys


def read_poly(path):
    rows = []
    for line in open(path):
        line = line.split('#', 1)[0].split()
        if line:
            rows.append(line)
    n, dim = int(rows[0][0]), int(rows[0][1])
    first = int(rows[1][0])  # 0- or 1-based ids
    points = [(float(r[1]), float(r[2])) for r in rows[1:1 + n]]
    k = 1 + n
    m = int(rows[k][0])
    segments = [(int(r[1]) - first, int(r[2]) - first) for r in rows[k + 1:k + 1 + m]]
    k += 1 + m
    h = int(rows[k][0])
    holes = [(float(r[1]), float(r[2])) for r in rows[k + 1:k + 1 + h]]
    return points, segments, holes


def main():
    src, copies, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    side = math.isqrt(copies)
    if side * side != copies:
        sys.exit(f"tile_poly.py: COPIES {copies} is not a perfect square")
    points, segments, holes = read_poly(src)
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    step = lambda extent: 2.0 ** math.ceil(math.log2(1.25 * extent))
    sx, sy = step(max(xs) - min(xs)), step(max(ys) - min(ys))
    n = len(points)
    with open(out, 'w') as f:
        f.write(f"{n * copies} 2 0 0\n")
        for c in range(copies):
            dx, dy = (c % side) * sx, (c // side) * sy
            for i, (x, y) in enumerate(points):
                f.write(f"{c * n + i} {x + dx!r} {y + dy!r}\n")
        f.write(f"{len(segments) * copies} 0\n")
        for c in range(copies):
            for i, (a, b) in enumerate(segments):
                f.write(f"{c * len(segments) + i} {c * n + a} {c * n + b}\n")
        f.write(f"{len(holes) * copies}\n")
        for c in range(copies):
            dx, dy = (c % side) * sx, (c // side) * sy
            for i, (x, y) in enumerate(holes):
                f.write(f"{c * len(holes) + i} {x + dx!r} {y + dy!r}\n")


if __name__ == "__main__":
    main()
