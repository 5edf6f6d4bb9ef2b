#!/usr/bin/python3
"""Scaling benchmark over input classes: every method of `mwst triangulate`, and `mwst bundle` of
the Delaunay triangulation, run as whole processes on the inputs of `mwst generate` at growing n.

For each class x n x method it runs the command line with a wall-time cap (killed past it) and an
address-space cap (RLIMIT_AS, so a runaway fails an allocation instead of swapping), and measures
wall time, CPU time (user + system, all threads) and peak resident memory (ru_maxrss of the process,
from wait4: the kernel's figure, the same as /usr/bin/time's %M), and reads the output triangle
count (and stop reason) from the --json report. It prints a Markdown table with time and bytes per
output triangle, and a growth column: CPU microseconds per triangle at this n divided by that at
the smallest n measured, beside log(n)/log(n0), the growth an O(n log n) method may show. A ratio
above --cliff-factor times log(n)/log(n0) is flagged CLIFF; a run stopped by a cap after a smaller n
of the same class and method finished is flagged too. MEM flags more than 300 bytes per triangle
counted above the baseline: the peak RSS of
`mwst triangulate` on three points (the binary and its libraries, about 10 MB), printed under the
table.

Methods: dt; dr (--min-angle 20, off-centers); brh (default k from 20 degrees); qtr; opt
(--time-limit, default 5/6 of the cap, as the issue's table ran it); bundle (`mwst bundle` of the dt
mesh; "triangles" is the dt mesh's count, "status" gives the bundle number K).

Usage:
  bench/scaling.py [--mwst build/mwst] [--classes uniform,circle] [--sizes 10k,40k,160k,1M]
                   [--methods dt,dr,brh,qtr,opt,bundle] [--time-cap 60] [--memory-cap-gb 6]
                   [--repeat 1] [--out table.md]
Defaults: every class, n = 10k and 40k, every method, 60 s, 6 GB: a few minutes on two cores when
nothing falls off a cliff, up to an hour when everything does.
"""
import argparse
import json
import math
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time

CLASSES = ["uniform", "kuzmin", "grid", "circle", "ellipse", "spiral", "clusters",
           "holes", "fan", "strip", "coastline"]
POLYGONS = {"holes", "fan", "strip", "coastline"}
METHODS = ["dt", "dr", "brh", "qtr", "opt", "bundle"]
BYTES_PER_TRIANGLE_GOAL = 300


def parse_size(text):
    text = text.strip().lower()
    scale = 1
    if text.endswith("k"):
        scale, text = 1000, text[:-1]
    elif text.endswith("m"):
        scale, text = 1000000, text[:-1]
    return int(float(text) * scale)


def size_name(n):
    if n % 1000000 == 0:
        return f"{n // 1000000}M"
    if n % 1000 == 0:
        return f"{n // 1000}k"
    return str(n)


class Run:
    """One measured process: wall and CPU seconds, peak RSS in bytes, how it ended."""

    def __init__(self, wall, cpu, peak_bytes, exit_code, capped, stderr):
        self.wall, self.cpu, self.peak_bytes = wall, cpu, peak_bytes
        self.exit_code, self.capped, self.stderr = exit_code, capped, stderr


def measure(argv, time_cap, memory_cap_bytes, stdout_path):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (memory_cap_bytes, memory_cap_bytes))
        os.setpgid(0, 0)

    with open(stdout_path, "wb") as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        proc = subprocess.Popen(argv, stdout=out, stderr=err, preexec_fn=limit)
        capped = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid == proc.pid:
                break
            if time.monotonic() - start > time_cap:
                capped = True
                os.killpg(proc.pid, signal.SIGKILL)
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.005)
        wall = time.monotonic() - start
        proc.returncode = 0  # reaped by wait4 above; keep Popen from waiting again
        err.seek(0)
        stderr = err.read().decode(errors="replace")
    code = os.waitstatus_to_exitcode(status)
    return Run(wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024, code, capped, stderr)


def method_argv(mwst, method, source, prefix, report, time_cap, opt_time_limit):
    if method == "bundle":
        return [mwst, "bundle", source, prefix[: -len("bundle")] + "dt", "--json"]
    argv = [mwst, "triangulate", source, "-o", prefix, "--method", method, "-q", "--json", report]
    if method == "dr":
        argv += ["--min-angle", "20", "--steiner", "offcenter"]
    if method == "opt":
        argv += ["--time-limit", f"{opt_time_limit:g}"]
    return argv


def remove_mesh(prefix):
    for ext in (".node", ".ele", ".poly"):
        try:
            os.remove(prefix + ext)
        except FileNotFoundError:
            pass


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--mwst", default=os.path.join(here, "..", "build", "mwst"))
    ap.add_argument("--classes", default=",".join(CLASSES))
    ap.add_argument("--sizes", default="10k,40k", help="e.g. 10k,40k,160k,1M")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--time-cap", type=float, default=60.0, help="wall seconds per run")
    ap.add_argument("--memory-cap-gb", type=float, default=6.0, help="address space per run")
    ap.add_argument("--opt-time-limit", type=float, default=None, help="default 5/6 of --time-cap")
    ap.add_argument("--cliff-factor", type=float, default=2.0,
                    help="flag growth above this times log(n)/log(n0)")
    ap.add_argument("--repeat", type=int, default=1, help="best of this many runs (by CPU time)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", default=None, help="directory for inputs and meshes (default: temporary)")
    ap.add_argument("--out", default=None, help="also write the Markdown table to this file")
    a = ap.parse_args()

    mwst = os.path.abspath(a.mwst)
    classes = [c for c in a.classes.split(",") if c]
    for c in classes:
        if c not in CLASSES:
            sys.exit(f"scaling.py: unknown class '{c}' (one of {', '.join(CLASSES)})")
    methods = [m for m in a.methods.split(",") if m]
    for m in methods:
        if m not in METHODS:
            sys.exit(f"scaling.py: unknown method '{m}' (one of {', '.join(METHODS)})")
    sizes = sorted(parse_size(s) for s in a.sizes.split(",") if s)
    opt_limit = a.opt_time_limit if a.opt_time_limit is not None else a.time_cap * 5 / 6
    memory_cap = int(a.memory_cap_gb * 2**30)
    work = a.work or tempfile.mkdtemp(prefix="mwst-scaling-")
    os.makedirs(work, exist_ok=True)

    # The baseline resident memory of the process: the binary and its shared libraries.
    tiny = os.path.join(work, "three.node")
    with open(tiny, "w") as f:
        f.write("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n")
    baseline = measure([mwst, "triangulate", tiny, "-o", os.path.join(work, "three.1"), "-q"],
                       a.time_cap, memory_cap, os.devnull).peak_bytes
    remove_mesh(os.path.join(work, "three.1"))

    header = ["class", "n", "method", "wall s", "CPU s", "peak MB", "triangles", "µs/tri (CPU)",
              "bytes/tri", "growth (vs log)", "status", "flags"]
    align = ["---", "---:", "---", "---:", "---:", "---:", "---:", "---:", "---:", "---:", "---", "---"]

    def table_text():
        lines = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
        lines += ["| " + " | ".join(row) + " |" for row in rows]
        return "\n".join(lines) + f"\n\nbytes/tri: peak RSS above the baseline of {baseline / 1e6:.1f} MB, per output triangle.\n"

    cap_text = f"> {a.time_cap:g} s"
    rows = []
    per_tri_at_first = {}   # (class, method) -> (n0, CPU µs per triangle)
    for cls in classes:
        for n in sizes:
            ext = ".poly" if cls in POLYGONS else ".node"
            source = os.path.join(work, f"{cls}-{size_name(n)}{ext}")
            subprocess.run([mwst, "generate", cls, str(n), "--seed", str(a.seed), "-o", source], check=True)
            for method in methods:
                prefix = os.path.join(work, f"{cls}-{size_name(n)}-{method}")
                report = prefix + ".json"
                if method == "bundle" and not os.path.exists(prefix[: -len("bundle")] + "dt.ele"):
                    rows.append([cls, size_name(n), method] + ["–"] * 7 + ["no dt mesh", ""])
                    continue
                argv = method_argv(mwst, method, source, prefix, report, a.time_cap, opt_limit)
                best = None
                for _ in range(a.repeat):
                    if os.path.exists(report):
                        os.remove(report)
                    r = measure(argv, a.time_cap, memory_cap,
                                report if method == "bundle" else os.devnull)
                    if best is None or (r.exit_code == 0 and r.cpu < best.cpu):
                        best = r
                    if r.exit_code != 0:
                        break
                r = best
                triangles, status = None, ""
                if r.capped:
                    status = cap_text
                elif r.exit_code != 0:
                    line = r.stderr.strip().splitlines()
                    status = f"exit {r.exit_code}" + (f": {line[-1][:60]}" if line else "")
                else:
                    try:
                        with open(report) as f:
                            info = json.load(f)
                        if method == "bundle":
                            triangles = info.get("triangle_count")
                            status = f"K = {info.get('bundle_number')}"
                        else:
                            triangles = info.get("triangles")
                            status = info.get("stop_reason", "")
                    except (OSError, ValueError) as e:
                        status = f"no report ({e.__class__.__name__})"
                if method != "dt":
                    remove_mesh(prefix)
                flags = []
                wall = f"{r.wall:.2f}"
                cpu = f"{r.cpu:.2f}"
                peak = f"{r.peak_bytes / 1e6:.0f}" if r.peak_bytes >= 1e6 else f"{r.peak_bytes / 1e6:.1f}"
                us = bpt = growth = "–"
                key = (cls, method)
                if triangles:
                    per_tri = r.cpu * 1e6 / triangles
                    us = f"{per_tri:.2f}"
                    b = max(0, r.peak_bytes - baseline) / triangles
                    bpt = f"{b:.0f}"
                    if b > BYTES_PER_TRIANGLE_GOAL:
                        flags.append("MEM")
                    if key not in per_tri_at_first:
                        per_tri_at_first[key] = (n, per_tri)
                    elif per_tri_at_first[key][1] is not None:
                        n0, first = per_tri_at_first[key]
                        ratio = per_tri / first
                        allowed = math.log(n) / math.log(n0)
                        growth = f"{ratio:.2f} (log {allowed:.2f})"
                        if ratio > a.cliff_factor * allowed:
                            flags.append("CLIFF")
                elif key in per_tri_at_first and per_tri_at_first[key][1] is not None and \
                        (r.capped or r.exit_code != 0):
                    flags.append("CLIFF")
                elif key not in per_tri_at_first:
                    per_tri_at_first[key] = (n, None)  # the smallest n failed: later rows unrated
                rows.append([cls, size_name(n), method, wall, cpu, peak,
                             str(triangles) if triangles else "–", us, bpt, growth, status,
                             " ".join(flags)])
                print(" | ".join(rows[-1]), file=sys.stderr, flush=True)
                if a.out:
                    with open(a.out, "w") as f:
                        f.write(table_text())
            remove_mesh(os.path.join(work, f"{cls}-{size_name(n)}-dt"))

    table = table_text()
    sys.stdout.write(table)
    if a.out:
        with open(a.out, "w") as f:
            f.write(table)


if __name__ == "__main__":
    main()
