#!/usr/bin/python3
"""The Python package against the Delaunay triangulators Python users have, and against its own C++.

1. 1M uniform points in the unit square (numpy, seed 1), triangulated three ways:
   mwst.triangulate (all cores, and one thread), scipy.spatial.Delaunay (qhull) and
   matplotlib.tri.Triangulation (qhull too). Wall and CPU seconds (CPU: all threads of this process).
2. mwst's Python overhead over the C++ call, measured inside the same call: the wall time of
   mwst.triangulate against (a) the library's triangulate() (report["seconds"]["total"], what
   `mwst triangulate` runs), and (b) triangulate() plus the library's to_arrays(), i.e.
   triangulate_arrays(), the C++ call that returns arrays (report["seconds"]["to_arrays"] added):
   (b) is what the binding itself adds (reading the numpy arrays, handing the library's vectors to
   numpy, the JSON report). Also `mwst triangulate` of the same points from a .node file, whose
   report gives the C++ call's time in a separate process.
3. The same for Delaunay refinement at 25 degrees of 100k uniform points.

Each mwst measurement is the best of --repeat runs (the machine may be loaded: compare CPU columns
too), each run's result dropped before the next unless it is the fastest so far (--keep-results:
all kept alive, so that every call writes memory the system must clear first); scipy and
matplotlib run once (about 10 s each).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [--cli build/mwst] [--repeat 3]
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np


def timed(call):
    """(result, wall seconds, CPU seconds of this process)."""
    wall, cpu = time.perf_counter(), time.process_time()
    result = call()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def best(call, repeat, keep=False):
    """The run with the least wall time of `repeat`: (result, wall, cpu). A run's result is freed
    before the next run unless it is the fastest so far, as in a loop that triangulates and drops
    each result (timeit's way); with `keep` every result stays alive until all runs are done, so
    that every call writes fresh memory the system must clear (--keep-results)."""
    kept, fastest = [], None
    for _ in range(repeat):
        run = timed(call)
        if keep:
            kept.append(run)
        if fastest is None or run[1] < fastest[1]:
            fastest = run
        del run
    return fastest


def write_node(path, points):
    with open(path, "w") as f:
        f.write(f"{len(points)} 2 0 0\n")
        np.savetxt(f, np.column_stack([np.arange(1, len(points) + 1), points]), fmt=["%d", "%.17g", "%.17g"])


def cli_seconds(cli, node, options, repeat):
    """The C++ call's seconds as `mwst triangulate` reports them (best of `repeat`), and the
    process's wall seconds (reading the .node and writing the mesh included)."""
    best_call = best_wall = float("inf")
    with tempfile.TemporaryDirectory() as out:
        for _ in range(repeat):
            t0 = time.perf_counter()
            done = subprocess.run([cli, "triangulate", node, "-o", os.path.join(out, "m"), "--json", "-", "-q", *options],
                                  check=True, capture_output=True, text=True)
            best_wall = min(best_wall, time.perf_counter() - t0)
            best_call = min(best_call, json.loads(done.stdout)["seconds"]["total"])
    return best_call, best_wall


def overhead_rows(name, points, kwargs, cli, cli_options, repeat, work, keep=False):
    import mwst

    rows = []
    for threads in (0, 1):
        mesh, wall, cpu = best(lambda: mwst.triangulate(points, threads=threads, **kwargs), repeat, keep)
        call = mesh.report["seconds"]["total"]
        arrays = call + mesh.report["seconds"]["to_arrays"]
        rows.append((f"{name}, threads={threads or 'all'}", len(mesh.triangles), wall, cpu, call, arrays))
        del mesh
    node = os.path.join(work, f"{name.replace(' ', '_')}.node")
    write_node(node, points)
    call, process = cli_seconds(cli, node, cli_options, repeat)
    print(f"  {name}: `mwst triangulate {' '.join(cli_options)}` on the same points: C++ call {call:.3f} s "
          f"(process {process:.3f} s with reading and writing files)")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", default=str(pathlib.Path(__file__).resolve().parents[1] / "build" / "mwst"),
                        help="the command line (default: build/mwst)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per mwst measurement (best kept)")
    parser.add_argument("--points", type=int, default=1_000_000, help="points of the Delaunay comparison")
    parser.add_argument("--dr-points", type=int, default=100_000, help="points of the DR comparison")
    parser.add_argument("--keep-results", action="store_true",
                        help="keep every run's result alive until all runs are done (each call then writes "
                             "fresh memory); by default a result is dropped before the next run, as in a loop")
    parser.add_argument("--overhead-only", action="store_true",
                        help="only parts 2-3 (no scipy or matplotlib, which take about 10 s each)")
    args = parser.parse_args()

    import mwst

    print(f"mwst {mwst.__version__}, numpy {np.__version__}, python {sys.version.split()[0]}, "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}")
    rng = np.random.default_rng(1)
    points = rng.random((args.points, 2))
    if not args.overhead_only:
        compare_triangulators(points, args)
    overhead_table(points, rng, args)


def compare_triangulators(points, args):
    """Part 1: mwst.triangulate against scipy's and matplotlib's Delaunay triangulations."""
    import matplotlib.tri
    import scipy.spatial

    import mwst

    print(f"scipy {scipy.__version__}, matplotlib {matplotlib.__version__}")

    print(f"\n1. Delaunay triangulation of {args.points:,} uniform points")
    print("| triangulator | triangles | wall s | CPU s | wall vs scipy |")
    print("|---|---:|---:|---:|---:|")
    results = []
    for threads in (0, 1):
        mesh, wall, cpu = best(lambda: mwst.triangulate(points, threads=threads), args.repeat)
        results.append((f"mwst.triangulate (threads={threads or 'all'})", len(mesh.triangles), wall, cpu))
    delaunay, wall, cpu = timed(lambda: scipy.spatial.Delaunay(points))
    results.append(("scipy.spatial.Delaunay (qhull)", len(delaunay.simplices), wall, cpu))
    scipy_wall = wall
    del delaunay
    triangulation, wall, cpu = timed(lambda: matplotlib.tri.Triangulation(points[:, 0], points[:, 1]))
    results.append(("matplotlib.tri.Triangulation (qhull)", len(triangulation.triangles), wall, cpu))
    del triangulation
    for name, triangles, wall, cpu in results:
        print(f"| {name} | {triangles:,} | {wall:.3f} | {cpu:.3f} | {wall / scipy_wall:.3f}x |")



def overhead_table(points, rng, args):
    """Parts 2-3: mwst's Python overhead over the C++ call."""
    kept = "every result kept alive" if args.keep_results else "each result dropped before the next run"
    print(f"\n2.-3. mwst's Python overhead over the C++ call (best of {args.repeat}, {kept})")
    with tempfile.TemporaryDirectory() as work:
        rows = overhead_rows(f"dt {args.points // 1000}k", points, {}, args.cli, ["--method", "dt"], args.repeat, work,
                             args.keep_results)
        dr_points = rng.random((args.dr_points, 2))
        rows += overhead_rows(f"dr 25 {args.dr_points // 1000}k", dr_points, {"method": "dr", "min_angle": 25},
                              args.cli, ["--method", "dr", "--min-angle", "25"], args.repeat, work,
                              args.keep_results)
    print("| run | triangles | Python wall s | Python CPU s | triangulate() s | overhead over it "
          "| triangulate_arrays() s | overhead over it |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, triangles, wall, cpu, call, arrays in rows:
        print(f"| {name} | {triangles:,} | {wall:.3f} | {cpu:.3f} | {call:.3f} | {100 * (wall - call) / call:.1f}% "
              f"| {arrays:.3f} | {100 * (wall - arrays) / arrays:.1f}% |")


if __name__ == "__main__":
    main()
