#!/usr/bin/env python3
"""memory_estimate.py -- the memory guard's estimate against measured peaks.

For each (kind, points, threads) it generates the points (.bin, kept in --data), runs
`gigatet triangulate POINTS.bin -t THREADS --stats` and prints one row: tets, the measured
peak RSS (ru_maxrss of the child, from wait4), the peak address space (VmPeak of
/proc/PID/status, polled until the process exits), the CLI's estimated_peak_bytes (the
library's gtet_estimate_memory plus the 24-byte-a-point input array the CLI holds) and
est/rss.  The guard must never be more than a few percent below the truth and not more than
about 25% above it at large n (src/api/memory.c says which constant to change).

usage: bench/memory_estimate.py PATH/TO/gigatet [--data DIR] [--kinds uniform,grid]
                                [--sizes 100000,1000000] [--threads 1,2] [--check]
"""
import argparse
import json
import os
import subprocess
import sys
import time


def vm_peak(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmPeak:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def run(cmd):
    """Run cmd; return (exit code, stdout, max rss bytes, vm peak bytes)."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    peak = 0
    while True:
        pid, status, ru = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        peak = max(peak, vm_peak(p.pid))
        time.sleep(0.01)
    out = p.stdout.read().decode()
    err = p.stderr.read().decode()
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.stderr.write(err)
    return p.returncode, out, ru.ru_maxrss * 1024, peak


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("gigatet")
    ap.add_argument("--data", default="/tmp/gtet-memory-data")
    ap.add_argument("--kinds", default="uniform")
    ap.add_argument("--sizes", default="100000,1000000")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.data, exist_ok=True)
    print("| kind | points | threads | tets | peak RSS MB | VmPeak MB | estimate MB | est/RSS "
          "| RSS B/tet |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for kind in a.kinds.split(","):
        for n in (int(s) for s in a.sizes.split(",")):
            pts = os.path.join(a.data, f"{kind}-{n}.bin")
            if not os.path.exists(pts):
                subprocess.run([a.gigatet, "generate", kind, str(n), "-o", pts, "-q"],
                               check=True)
            for t in (int(s) for s in a.threads.split(",")):
                cmd = [a.gigatet, "triangulate", pts, "-t", str(t), "--stats"]
                if a.check:
                    cmd.append("--check")
                rc, out, rss, peak = run(cmd)
                if rc != 0:
                    print(f"| {kind} | {n} | {t} | exit {rc} | | | | | |")
                    continue
                st = json.loads(out.strip().splitlines()[-1])
                est = st["estimated_peak_bytes"]
                print(f"| {kind} | {st['points']} | {t} | {st['tets']} | {rss / 1e6:.1f} "
                      f"| {peak / 1e6:.1f} | {est / 1e6:.1f} | {est / rss:.3f} "
                      f"| {rss / max(st['tets'], 1):.1f} |", flush=True)


if __name__ == "__main__":
    main()
