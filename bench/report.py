#!/usr/bin/env python3
"""report.py RAW.tsv [--runs N] [--commands TEXT] -- the markdown table of a bench/run.sh run.

Per input and tool, over the successful runs: median wall and CPU seconds of the meshing
(each tool's own timer; TetGen has CPU only), minimum wall, the ratios of the medians to CGAL
sequential's on the same input in the same run (< 1 is faster than CGAL), the number of tets,
the median peak RSS and RSS bytes per tet.  Then one table of ratios per input against CGAL
sequential (wall medians): gigatet -t 1 and -t 2, the speed-up -t 1 / -t 2, and the peers
(CGAL with 2 TBB threads, HXT 1 and 2 threads).  Then the issue goals that the run can decide
(gigatet rows only), each with the figures it used.
"""
import argparse
import csv
import datetime
import math
import os
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
    ok = [r for r in rs if not r["note"].startswith("failed")]
    if not ok:
        return None
    secs = [float(r["seconds"]) for r in ok if not math.isnan(float(r["seconds"]))]
    cpus = [float(r["cpu"]) for r in ok if not math.isnan(float(r["cpu"]))]
    tets = statistics.mode(int(r["tets"]) for r in ok)
    rss = statistics.median(int(r["rss_kb"]) for r in ok)
    nan = float("nan")
    return {"median": statistics.median(secs) if secs else nan,
            "min": min(secs) if secs else nan,
            "cpu": statistics.median(cpus) if cpus else nan, "n": len(ok), "of": len(rs),
            "tets": tets, "rss_mib": rss / 1024.0, "bpt": rss * 1024.0 / tets if tets else 0,
            "wall": any("wall" in r["note"] for r in ok),
            "pcpu": any("cpu-process" in r["note"] for r in ok)}


def fmt(x, spec="%.3f"):
    return "-" if x is None or math.isnan(x) else spec % x


def ratio(a, b):
    return None if a is None or b is None or math.isnan(a) or math.isnan(b) or not b else a / b


def ratio_table(inputs, med):
    """Per input: -t 1 / CGAL, -t 2 / CGAL, speed-up, and the peers / CGAL (wall medians)."""
    cols = [("`-t 1` ÷ CGAL", "gigatet1", None), ("`-t 2` ÷ CGAL", "gigatet2", None),
            ("speed-up `-t 1` / `-t 2`", "gigatet1", "gigatet2"),
            ("CGAL-TBB 2 ÷ CGAL", "cgal_par2", None), ("HXT 1 ÷ CGAL", "hxt1", None),
            ("HXT 2 ÷ CGAL", "hxt2", None)]
    rows = []
    for inp in inputs:
        c = med(inp, "cgal_seq")
        cells = []
        for _, a, b in cols:
            x = med(inp, a)
            cells.append(ratio(x, med(inp, b)) if b else ratio(x, c))
        if any(v is not None for v in cells):
            rows.append((inp, c, cells))
    if not rows:
        return
    print()
    print("## Ratios against CGAL sequential (wall medians of the same run)")
    print()
    print("| input | CGAL seq s | " + " | ".join(h for h, _, _ in cols) + " |")
    print("|---|---:|" + "---:|" * len(cols))
    for inp, c, cells in rows:
        print("| %s | %s | %s |" % (inp, fmt(c), " | ".join(fmt(v, "%.2f") for v in cells)))


def issue18_goals(inputs, med):
    """Issue 18's goals, for the families whose prefix names them (bench/run.sh)."""
    out = []

    def check(inp, what, x, op, goal):
        if x is None:
            return
        ok = x <= goal if op == "<=" else x >= goal
        out.append("issue 18: %s on %s = %.2f (goal %s %s): %s"
                   % (what, inp, x, op, goal, "met" if ok else "NOT met"))

    for inp in inputs:
        c, g1, g2 = med(inp, "cgal_seq"), med(inp, "gigatet1"), med(inp, "gigatet2")
        t1, t2, sp = ratio(g1, c), ratio(g2, c), ratio(g1, g2)
        if inp.startswith("scan"):
            check(inp, "-t 1 / CGAL", t1, "<=", 0.55)
            check(inp, "-t 2 / CGAL", t2, "<=", 0.32)
            check(inp, "speed-up", sp, ">=", 1.7)
        elif inp.startswith("sph") or inp.startswith("par"):
            check(inp, "-t 1 / CGAL", t1, "<=", 0.6)
            if inp.startswith("sph"):
                check(inp, "speed-up", sp, ">=", 1.6)
        elif inp.startswith("clu"):
            check(inp, "speed-up", sp, ">=", 1.7)
        elif inp.startswith("mix"):
            check(inp, "-t 1 / CGAL", t1, "<=", 1.0)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("raw")
    ap.add_argument("--runs", type=int, default=0)
    ap.add_argument("--commands", default="")
    ap.add_argument("--load", default="", help="load averages before / after the run")
    a = ap.parse_args()
    rows, inputs, tools = load(a.raw)
    order = [t for t in TOOL_NAMES if t in tools] + [t for t in tools if t not in TOOL_NAMES]
    print("# gigatet benchmark, %s" % datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"))
    print()
    print("Machine: %s, %s, %s CPUs (shared with other jobs: load average %s); %d runs per tool,"
          " interleaved round-robin; medians. Seconds are each tool's own timing of the meshing"
          " (file reading excluded), wall and process CPU (all threads; TetGen reports CPU"
          " only); peak RSS of the whole process (input included); bytes/tet = peak RSS / tets."
          % (platform.machine(), platform.platform(terse=True), os.cpu_count(),
             a.load or "?", a.runs))
    sums = {}
    for inp in inputs:
        print()
        print("## %s" % inp)
        print()
        print("| tool | wall s | CPU s | min wall s | wall vs CGAL seq | CPU vs CGAL seq | tets |"
              " peak RSS MiB | bytes/tet | runs |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        s0 = summary(rows.get((inp, "cgal_seq"), []))
        base = s0["median"] if s0 else None
        base_cpu = s0["cpu"] if s0 else None
        for t in order:
            s = summary(rows.get((inp, t), []))
            sums[(inp, t)] = s
            if s is None:
                if rows.get((inp, t)):
                    print("| %s | failed | | | | | | | | 0/%d |" % (TOOL_NAMES.get(t, t),
                                                                   len(rows[(inp, t)])))
                continue
            print("| %s | %s%s | %s%s | %s | %s | %s | %d | %.0f | %.0f | %d/%d |" % (
                TOOL_NAMES.get(t, t), fmt(s["median"]), " (process)" if s["wall"] else "",
                fmt(s["cpu"]), " (process)" if s["pcpu"] else "", fmt(s["min"]),
                fmt(ratio(s["median"], base), "%.2f"), fmt(ratio(s["cpu"], base_cpu), "%.2f"),
                s["tets"], s["rss_mib"], s["bpt"], s["n"], s["of"]))
        counts = {sums[(inp, t)]["tets"] for t in order if sums.get((inp, t))}
        if len(counts) > 1:
            print()
            print("Tet counts differ between tools on %s: %s (expected on grids, where the "
                  "perturbation rules differ; a bug on random points)." % (inp, sorted(counts)))

    goals = []

    def med(inp, t, key="median"):
        s = sums.get((inp, t))
        return s[key] if s and not math.isnan(s[key]) else None

    ratio_table(inputs, med)
    goals += issue18_goals(inputs, med)

    for inp in inputs:
        g1, c = med(inp, "gigatet1"), med(inp, "cgal_seq")
        if inp.startswith("u") and g1 and c:
            goals.append("gigatet -t 1 / CGAL seq on %s = %.2f wall (goal <= 0.5 on 1M): %s"
                         % (inp, g1 / c, "met" if g1 / c <= 0.5 else "NOT met"))
        g1c, cc = med(inp, "gigatet1", "cpu"), med(inp, "cgal_seq", "cpu")
        if inp.startswith("u") and g1c and cc:
            goals.append("gigatet -t 1 / CGAL seq on %s = %.2f CPU (gigatet's CPU includes "
                         "reading the file unless its stats give it)" % (inp, g1c / cc))
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
