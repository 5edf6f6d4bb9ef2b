#!/usr/bin/env python3
"""Light meshes of a polygon with holes: the weights (total edge length) of mwst's methods.

Triangulates a polygon with two holes (or the .poly file given) with
  dt        the constrained Delaunay triangulation (no Steiner points),
  dr        Delaunay refinement at 25 degrees,
  brh+flip  bundle removal, then weight-reducing flips,
  opt       mwst's weight optimiser,
prints each mesh's weight, and draws the four side by side into a matplotlib figure.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/light_mesh.py [INPUT.poly] [-o light_mesh.png]
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mwst  # noqa: E402


def polygon_with_holes():
    """A wavy 24-gon with a square hole and a triangular hole: (vertices, segments, holes)."""
    outer = [(10 * (1 + 0.15 * math.cos(5 * a)) * math.cos(a), 10 * (1 + 0.15 * math.cos(5 * a)) * math.sin(a))
             for a in np.linspace(0, 2 * math.pi, 24, endpoint=False)]
    square = [(-5, -2), (-1, -2), (-1, 2), (-5, 2)]
    triangle = [(2, -3), (6, 0), (2, 3)]
    vertices, segments = [], []
    for ring in (outer, square, triangle):
        first = len(vertices)
        vertices += ring
        segments += [(first + i, first + (i + 1) % len(ring)) for i in range(len(ring))]
    holes = [(-3, 0), (3, 0)]
    return mwst.Pslg(vertices, segments, holes, source="polygon with two holes")


METHODS = [
    ("dt", {"method": "dt"}),
    ("dr 25°", {"method": "dr", "min_angle": 25}),
    ("brh+flip", {"method": "brh", "flip": True}),
    ("opt", {"method": "opt"}),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input", nargs="?", help="a Triangle .poly file (default: a polygon with two holes)")
    parser.add_argument("-o", "--output", default="light_mesh.png", help="the figure (.png, .svg, .pdf)")
    args = parser.parse_args()
    pslg = mwst.read(args.input) if args.input else polygon_with_holes()

    fig, axes = plt.subplots(1, len(METHODS), figsize=(4 * len(METHODS), 4.4))
    print(f"{pslg.source or args.input}: {len(pslg.vertices)} vertices, {len(pslg.segments)} segments, "
          f"{len(pslg.holes)} holes")
    for ax, (name, options) in zip(axes, METHODS):
        mesh = mwst.triangulate(pslg, **options)
        r = mesh.report
        print(f"  {name:9s} weight {r['weight_total']:12.4f}  ({r['triangles']} triangles, "
              f"{r['steiner']} Steiner points, angles {r['min_angle']:.1f}-{r['max_angle']:.1f}°)")
        mwst.plot(mesh, ax)
        ax.set_title(f"{name}: weight {r['weight_total']:.1f}")
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"  wrote {args.output}")


if __name__ == "__main__":
    main()
