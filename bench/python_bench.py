#!/usr/bin/python3
"""python_bench.py -- gigatet.Delaunay against scipy.spatial.Delaunay (Qhull) and against the
gigatet CLI's own kernel time, on uniform random points (not a test; goals: >= 20x faster
than scipy with 2 threads, <= 1.15x the CLI's kernel time on 1M points).

    /usr/bin/python3 bench/python_bench.py [--sizes 100000 1000000] [--runs 3] [--threads 2]
                                           [--cli build/gigatet] [--no-scipy]

Each repetition runs every tool once on each size, in a freshly shuffled order (interleaved
runs); the table gives medians.  Columns:
  gigatet       wall time of gigatet.Delaunay(points, threads) (the kernel, GIL released;
                simplices & co. are computed on first use)
  + arrays      the same, then simplices and neighbors fetched (scipy builds those eagerly)
  scipy         wall time of scipy.spatial.Delaunay(points)
  CLI kernel    `gigatet triangulate FILE.bin -t THREADS --stats`: seconds.kernel, the time of
                gtet_triangulate alone inside the CLI (no file reading)
gigatet must be importable by the interpreter running this (see README: Use it from Python).
"""
import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import gigatet


def write_bin(path, pts):
    with open(path, "wb") as f:
        f.write(np.uint64(len(pts)).tobytes())
        f.write(np.ascontiguousarray(pts, dtype="<f8").tobytes())


def run_gigatet(pts, threads):
    t = time.perf_counter()
    d = gigatet.Delaunay(pts, threads=threads)
    wall = time.perf_counter() - t
    d.simplices, d.neighbors
    full = time.perf_counter() - t
    return {"gigatet": wall, "gigatet+arrays": full, "tets": d.nsimplex}


def run_scipy(pts):
    from scipy.spatial import Delaunay
    t = time.perf_counter()
    d = Delaunay(pts)
    return {"scipy": time.perf_counter() - t, "scipy_tets": d.nsimplex}


def run_cli(cli, path, threads):
    out = subprocess.run([cli, "triangulate", path, "-t", str(threads), "--stats"],
                         check=True, capture_output=True, text=True).stdout
    stats = json.loads(next(line for line in out.splitlines() if line.startswith("{")))
    return {"cli_kernel": stats["seconds"]["kernel"], "cli_tets": stats["tets"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100000, 1000000])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cli", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                  "gigatet"))
    ap.add_argument("--no-scipy", action="store_true")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    have_cli = os.access(args.cli, os.X_OK)
    if not have_cli:
        print("python_bench: no CLI at %s: its column is skipped" % args.cli, file=sys.stderr)
    tmp = tempfile.mkdtemp(prefix="gtet-pybench-")
    data = {}
    for n in args.sizes:
        pts = np.random.default_rng(args.seed).random((n, 3))
        path = os.path.join(tmp, "u%d.bin" % n)
        write_bin(path, pts)
        data[n] = (pts, path)
    times = {n: {} for n in args.sizes}
    order = random.Random(args.seed)
    for rep in range(args.runs):
        jobs = [(n, tool) for n in args.sizes for tool in ("gigatet", "scipy", "cli")
                if not (tool == "scipy" and args.no_scipy) and not (tool == "cli" and not have_cli)]
        order.shuffle(jobs)
        for n, tool in jobs:
            pts, path = data[n]
            if tool == "gigatet":
                r = run_gigatet(pts, args.threads)
            elif tool == "scipy":
                r = run_scipy(pts)
            else:
                r = run_cli(args.cli, path, args.threads)
            for k, v in r.items():
                times[n].setdefault(k, []).append(v)
            print("run %d  n=%-8d %-8s %s" % (rep + 1, n, tool,
                  " ".join("%s=%.3f" % (k, v) if isinstance(v, float) else "%s=%d" % (k, v)
                           for k, v in r.items())), file=sys.stderr, flush=True)
    for f in os.listdir(tmp):
        os.unlink(os.path.join(tmp, f))
    os.rmdir(tmp)

    def med(n, k):
        v = times[n].get(k)
        return statistics.median(v) if v else float("nan")

    print("\n%s, %d threads, medians of %d interleaved runs (seconds)\n" % (
        "uniform random points in the unit cube", args.threads, args.runs))
    print("| points | gigatet.Delaunay | + simplices, neighbors | scipy.spatial.Delaunay "
          "| scipy / gigatet | CLI kernel | gigatet / CLI kernel |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for n in args.sizes:
        g, ga, s, c = med(n, "gigatet"), med(n, "gigatet+arrays"), med(n, "scipy"), \
            med(n, "cli_kernel")
        print("| %s | %.3f s | %.3f s | %s | %s | %s | %s |" % (
            "{:,}".format(n), g, ga,
            "%.2f s" % s if s == s else "-", "%.1f×" % (s / g) if s == s else "-",
            "%.3f s" % c if c == c else "-", "%.3f" % (g / c) if c == c else "-"))
        tets = set(times[n].get("tets", []) + times[n].get("cli_tets", []))
        if len(tets) > 1:
            print("python_bench: tet counts differ: %s" % sorted(tets), file=sys.stderr)


if __name__ == "__main__":
    main()
