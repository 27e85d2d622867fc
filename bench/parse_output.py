#!/usr/bin/env python3
"""parse_output.py TOOL STDOUT_FILE WALL CPU -- print "WALL_S CPU_S TETS [NOTE]" for one run.

WALL and CPU are the whole process's (from /usr/bin/time: %e, %U+%S), used only as fallbacks.
The meshing time each tool reports about itself, so file reading is excluded where it can be:
  cgal_*   bench_cgal --time:  "... tets M seconds S cpu C"  (S wall, C process CPU)
  hxt*     hxt_peer:           "... tets M seconds S cpu C"
  tetgen   tetgen -NEF:        "Delaunay seconds:  S" -- TetGen measures it with clock(), i.e.
           process CPU time: reported as CPU, wall "nan"; and "Mesh tetrahedra: M"
  gigatet* the JSON object of --stats: seconds_total (or a "total" inside a "seconds"/"time"
           object) and tets; failing that the summary line's "tets"/"seconds"; failing that
           the process's wall time (note "wall": it then includes reading the file).  CPU is
           the whole process's (note "cpu-process": it includes reading the file).
Exit 1 (nothing printed) when the output has no figure: run.sh records the run as failed.
"""
import json
import re
import sys


def find_key(obj, names):
    """First value of any key in names, depth-first through nested objects."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k in names and isinstance(v, (int, float)):
                return v
        for v in obj.values():
            r = find_key(v, names)
            if r is not None:
                return r
    return None


def gigatet(text, wall, cpu):
    secs = tets = None
    start, end = text.find("{"), text.rfind("}")
    if 0 <= start < end:
        try:
            obj = json.loads(text[start:end + 1])
            secs = find_key(obj, ("seconds_total", "total_seconds"))
            if secs is None:
                for k in ("seconds", "time", "times"):
                    if isinstance(obj.get(k), dict):
                        secs = find_key(obj[k], ("total", "kernel"))
            tets = find_key(obj, ("tets", "num_tets", "tetrahedra"))
        except ValueError:
            pass
    if secs is None:
        num = r"([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)"
        m = re.search(num + r"\s*(?:s|seconds)\b", text) or \
            re.search(r"seconds[\s:=\"]+" + num, text)
        secs = float(m.group(1)) if m else None
    if tets is None:
        m = re.search(r"([0-9]+)\s+tets\b", text) or re.search(r"tets[\s:=]+([0-9]+)", text)
        tets = int(m.group(1)) if m else None
    note = "cpu-process"
    if secs is None:
        secs, note = wall, "wall,cpu-process"
    if tets is None:
        return None
    return secs, cpu, int(tets), note


def main(argv):
    tool, path = argv[1], argv[2]
    wall, cpu = float(argv[3] or "nan"), float(argv[4] or "nan")
    text = open(path, errors="replace").read()
    r = None
    if tool.startswith("cgal") or tool.startswith("hxt"):
        m = re.search(r"tets (\d+) seconds ([0-9.eE+-]+) cpu ([0-9.eE+-]+)", text)
        if m:
            r = float(m.group(2)), float(m.group(3)), int(m.group(1)), ""
    elif tool == "tetgen":
        s = re.search(r"Delaunay seconds:\s*([0-9.eE+-]+)", text)
        t = re.search(r"Mesh tetrahedra:\s*(\d+)", text)
        if s and t:
            r = float("nan"), float(s.group(1)), int(t.group(1)), ""
    elif tool.startswith("gigatet"):
        r = gigatet(text, wall, cpu)
    if r is None:
        return 1
    print("%.6f %.6f %d %s" % r)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
