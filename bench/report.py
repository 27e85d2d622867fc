#!/usr/bin/env python3
"""report.py RAW.tsv [--runs N] [--commands TEXT] -- the markdown table of a bench/run.sh run.

Per input and tool: median and minimum of the reported seconds over the successful runs,
the ratio of the medians to CGAL sequential's on the same input in the same run (< 1 is faster
than CGAL), the number of tets, the median peak RSS and RSS bytes per tet.  Then the issue
goals that the run can decide (gigatet rows only), each with the figures it used.
"""
import argparse
import csv
import datetime
import math
import platform
import statistics
from collections import OrderedDict, defaultdict

TOOL_NAMES = OrderedDict([
    ("gigatet1", "gigatet -t 1"), ("gigatet2", "gigatet -t 2"),
    ("cgal_seq", "CGAL Delaunay_triangulation_3, sequential"),
    ("cgal_par2", "CGAL parallel (TBB, 2 threads)"),
    ("hxt1", "HXT (libgmsh 4.8), 1 thread"), ("hxt2", "HXT (libgmsh 4.8), 2 threads"),
    ("tetgen", "TetGen 1.5 (-NEF)"),
])


def load(path):
    rows = defaultdict(list)
    inputs, tools = OrderedDict(), OrderedDict()
    with open(path) as f:
        for r in csv.DictReader(f, delimiter="\t"):
            inputs[r["input"]] = 1
            tools[r["tool"]] = 1
            rows[(r["input"], r["tool"])].append(r)
    return rows, list(inputs), list(tools)


def summary(rs):
    ok = [r for r in rs if not r["note"].startswith("failed") and
          not math.isnan(float(r["seconds"]))]
    if not ok:
        return None
    secs = [float(r["seconds"]) for r in ok]
    tets = statistics.mode(int(r["tets"]) for r in ok)
    rss = statistics.median(int(r["rss_kb"]) for r in ok)
    return {"median": statistics.median(secs), "min": min(secs), "n": len(ok), "of": len(rs),
            "tets": tets, "rss_mib": rss / 1024.0, "bpt": rss * 1024.0 / tets if tets else 0,
            "wall": any(r["note"] == "wall" for r in ok)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("raw")
    ap.add_argument("--runs", type=int, default=0)
    ap.add_argument("--commands", default="")
    a = ap.parse_args()
    rows, inputs, tools = load(a.raw)
    order = [t for t in TOOL_NAMES if t in tools] + [t for t in tools if t not in TOOL_NAMES]
    print("# gigatet benchmark, %s" % datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"))
    print()
    print("Machine: %s, %s; %d runs per tool, interleaved round-robin; medians. Seconds are each"
          " tool's own timing of the meshing (file reading excluded); peak RSS of the whole"
          " process (input included); bytes/tet = peak RSS / tets." % (
              platform.machine(), platform.platform(terse=True), a.runs))
    sums = {}
    for inp in inputs:
        print()
        print("## %s" % inp)
        print()
        print("| tool | median s | min s | vs CGAL seq | tets | peak RSS MiB | bytes/tet | runs |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        base = None
        s0 = summary(rows.get((inp, "cgal_seq"), []))
        if s0:
            base = s0["median"]
        for t in order:
            s = summary(rows.get((inp, t), []))
            sums[(inp, t)] = s
            if s is None:
                if rows.get((inp, t)):
                    print("| %s | failed | | | | | | 0/%d |" % (TOOL_NAMES.get(t, t),
                                                             len(rows[(inp, t)])))
                continue
            ratio = "%.2f" % (s["median"] / base) if base else "-"
            print("| %s | %.3f%s | %.3f | %s | %d | %.0f | %.0f | %d/%d |" % (
                TOOL_NAMES.get(t, t), s["median"], " (wall)" if s["wall"] else "", s["min"],
                ratio, s["tets"], s["rss_mib"], s["bpt"], s["n"], s["of"]))
        counts = {sums[(inp, t)]["tets"] for t in order if sums.get((inp, t))}
        if len(counts) > 1:
            print()
            print("Tet counts differ between tools on %s: %s (expected on grids, where the "
                  "perturbation rules differ; a bug on random points)." % (inp, sorted(counts)))

    goals = []

    def med(inp, t):
        s = sums.get((inp, t))
        return s["median"] if s else None

    for inp in inputs:
        g1, c = med(inp, "gigatet1"), med(inp, "cgal_seq")
        if inp.startswith("u") and g1 and c:
            goals.append("gigatet -t 1 / CGAL seq on %s = %.2f (goal <= 0.5 on 1M): %s"
                         % (inp, g1 / c, "met" if g1 / c <= 0.5 else "NOT met"))
        g2 = med(inp, "gigatet2")
        if inp.startswith("u") and g1 and g2:
            goals.append("speed-up -t 2 over -t 1 on %s = %.2f (goal >= 1.8 on 4M): %s"
                         % (inp, g1 / g2, "met" if g1 / g2 >= 1.8 else "NOT met"))
        if inp.startswith("u") and g2 and c:
            goals.append("gigatet -t 2 / CGAL seq on %s = %.2f (goal <= 0.28): %s"
                         % (inp, g2 / c, "met" if g2 / c <= 0.28 else "NOT met"))
        s = sums.get((inp, "gigatet1"))
        if inp == "u10M" and s:
            goals.append("gigatet peak RSS per tet on u10M = %.0f bytes (goal <= 64): %s"
                         % (s["bpt"], "met" if s["bpt"] <= 64 else "NOT met"))
    if med("g100", "gigatet1") and med("u1M", "gigatet1"):
        q = med("g100", "gigatet1") / med("u1M", "gigatet1")
        goals.append("gigatet -t 1 grid 100^3 / uniform 1M = %.2f (goal <= 1.5): %s"
                     % (q, "met" if q <= 1.5 else "NOT met"))
    if goals:
        print()
        print("## Goals")
        print()
        for g in goals:
            print("- " + g)
    if a.commands:
        print()
        print("## Commands (one run each; bench/run.sh)")
        print()
        print("```")
        print(a.commands.strip())
        print("```")


if __name__ == "__main__":
    main()
