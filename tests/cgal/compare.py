#!/usr/bin/env python3
"""compare.py -- differential test: gigatet's tets must be CGAL's tets, on every point set.

    compare.py --cgal CGAL_DT [--gtet GTET_DT] [--skip-cgal-self] [--small]
               [--families A,B,..] [--list]

For each family of pointsets.py (random and degenerate sets) the point set is written as .bin
and handed to the reference, tests/cgal/cgal_dt (CGAL Delaunay_triangulation_3, Epick), which
prints the canonical tet list (4 sorted first-occurrence input indices per finite tet, lines
sorted).  The checks:

  unless --skip-cgal-self (CGAL against itself: these validate the driver and the form):
    * CGAL parallel (TBB, 2 threads) prints the same list as CGAL sequential;
    * CGAL on a shuffled copy prints the same list once its indices are mapped back;
  always:
    * the header's vertex/duplicate counts equal the distinct points counted here;
    * a list with one tet removed is reported as different (the comparison can fail).
  with --gtet (gigatet's tests/cgal/gtet_dt):
    * gigatet -t 1, -t 2, and -t 1 on the shuffled copy print CGAL's list.

Why equality is the right test: both programs claim the unique Delaunay tetrahedrization of
the distinct points under the same symbolic perturbation (Devillers-Teillaud, lexicographic),
which depends on the point set only; so any difference is a bug in one of the two.  A failing
family prints the first differing tets with their coordinates (hex floats) and keeps its input
as cgal_diff_failures/<family>.bin in the working directory, for `cgal_dt`/`gtet_dt` by hand.
Exit status 0 when every check passes, 1 otherwise.
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pointsets  # noqa: E402


class Canon:
    """A canonical list: header fields, the body text as printed, and the tets parsed lazily
    (equal texts are equal lists; parsing 10^6 lines is the driver's main cost)."""

    def __init__(self, header, body=None, tets=None):
        self.header = header  # dict: points, vertices, duplicates, tets
        self.body = body
        self._tets = tets

    @property
    def tets(self):
        if self._tets is None:
            v = list(map(int, self.body.split()))
            self._tets = list(zip(v[0::4], v[1::4], v[2::4], v[3::4]))
        return self._tets


def parse(text, who):
    head, _, body = text.partition("\n")
    if not head.startswith("# gtet-canonical "):
        raise RuntimeError("%s: no canonical header in its output" % who)
    f = head.split()[2:]
    header = {f[i]: int(f[i + 1]) for i in range(0, len(f) - 1, 2)}
    if body.count("\n") != header.get("tets", -1):
        raise RuntimeError("%s: header says %s tets, %d lines follow"
                           % (who, header.get("tets"), body.count("\n")))
    return Canon(header, body=body)


def run(cmd, who, timeout):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError("%s exited %d: %s" % (" ".join(cmd), p.returncode,
                                                 p.stderr.decode(errors="replace").strip()))
    return parse(p.stdout.decode(), who)


def first_occurrence(pts):
    """first[i] = smallest j with pts[j] == pts[i]; tuples of floats compare -0.0 == 0.0."""
    seen = {}
    return [seen.setdefault(p, i) for i, p in enumerate(pts)]


def relabel(canon, perm, first_orig):
    """Canonical list of a shuffled copy (point j of the copy is point perm[j] of the original)
    expressed in the original's first-occurrence ids."""
    m = [first_orig[perm[j]] for j in range(len(perm))]
    return Canon(canon.header, tets=sorted(tuple(sorted((m[a], m[b], m[c], m[d])))
                                           for a, b, c, d in canon.tets))


def describe(pts, t):
    return "(%s)" % ", ".join("%d:[%s]" % (i, " ".join(float.hex(c) for c in pts[i])) for i in t)


def differ(ref, got, pts, what, out):
    """Reports to out and returns True when the two canonical lists differ."""
    if ref.header == got.header and (
            (ref.body is not None and ref.body == got.body) or ref.tets == got.tets):
        return False
    out.append("  FAIL %s" % what)
    if ref.header != got.header:
        out.append("    headers: reference %s, got %s" % (ref.header, got.header))
    a, b = set(ref.tets), set(got.tets)
    only_ref = sorted(a - b)
    only_got = sorted(b - a)
    out.append("    %d tets only in the reference, %d only in the other" %
               (len(only_ref), len(only_got)))
    for t in only_ref[:5]:
        out.append("    - %s" % describe(pts, t))
    for t in only_got[:5]:
        out.append("    + %s" % describe(pts, t))
    if not only_ref and not only_got:
        out.append("    same tet set, different multiplicities or order")
    return True


def check_family(name, args, tmp):
    pts = pointsets.family(name, args.small)
    first = first_occurrence(pts)
    distinct = sum(1 for i, f in enumerate(first) if f == i)
    path = os.path.join(tmp, name + ".bin")
    pointsets.write_bin(path, pts)
    perm = list(range(len(pts)))
    random.Random("shuffle/" + name).shuffle(perm)
    spts = [pts[j] for j in perm]
    spath = os.path.join(tmp, name + "-shuffled.xyz")  # the text reader, on every family
    pointsets.write_xyz(spath, spts)

    out = []
    t = args.timeout
    ref = run([args.cgal, path], "cgal", t)
    if ref.header.get("points") != len(pts) or ref.header.get("vertices") != distinct or \
            ref.header.get("duplicates") != len(pts) - distinct:
        out.append("  FAIL cgal header %s, expected points %d vertices %d"
                   % (ref.header, len(pts), distinct))
    if ref.tets:
        broken = Canon(dict(ref.header, tets=len(ref.tets) - 1), tets=ref.tets[1:])
        if not differ(ref, broken, pts, "(negative control)", []):
            out.append("  FAIL the comparison did not notice a removed tet")
    elif distinct >= 4:
        out.append("  FAIL cgal gave no tets for %d distinct points" % distinct)
    checks = []  # (what, command, shuffled?)
    if not args.skip_cgal_self:
        checks += [("CGAL parallel (2 threads) vs CGAL sequential",
                    [args.cgal, "--parallel", "2", path], False),
                   ("CGAL on the shuffled input vs CGAL", [args.cgal, spath], True)]
    if args.gtet:
        checks += [("gigatet -t 1 vs CGAL", [args.gtet, "-t", "1", path], False),
                   ("gigatet -t 2 vs CGAL", [args.gtet, "-t", "2", path], False),
                   ("gigatet on the shuffled input vs CGAL", [args.gtet, "-t", "1", spath], True)]
    for what, cmd, shuffled in checks:
        try:  # one failing program must not hide the other checks, nor lose the input
            got = run(cmd, what, t)
        except (RuntimeError, OSError, subprocess.TimeoutExpired) as e:
            out.append("  FAIL %s: %s" % (what, e))
            continue
        differ(ref, relabel(got, perm, first) if shuffled else got, pts, what, out)
    if out:
        os.makedirs("cgal_diff_failures", exist_ok=True)
        pointsets.write_bin(os.path.join("cgal_diff_failures", name + ".bin"), pts)
        pointsets.write_xyz(os.path.join("cgal_diff_failures", name + "-shuffled.xyz"), spts)
    return len(pts), distinct, len(ref.tets), out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cgal", required=True, help="path of tests/cgal/cgal_dt")
    ap.add_argument("--gtet", help="path of tests/cgal/gtet_dt (omit: CGAL self-checks only)")
    ap.add_argument("--skip-cgal-self", action="store_true",
                    help="skip CGAL parallel / shuffled runs (a separate test does them)")
    ap.add_argument("--small", action="store_true", help="sanitizer-sized point sets")
    ap.add_argument("--families", help="comma-separated subset of: " +
                    ",".join(pointsets.FAMILIES))
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per program run")
    ap.add_argument("--list", action="store_true", help="list the families and exit")
    args = ap.parse_args(argv)
    if args.list:
        print("\n".join(pointsets.FAMILIES))
        return 0
    names = args.families.split(",") if args.families else list(pointsets.FAMILIES)
    for n in names:
        if n not in pointsets.FAMILIES:
            ap.error("unknown family %r" % n)
    failed = 0
    with tempfile.TemporaryDirectory(prefix="gtet-cgal-") as tmp:
        for name in names:
            t0 = time.monotonic()
            try:
                npts, nv, nt, out = check_family(name, args, tmp)
                status = "FAIL" if out else "ok"
                print("%-4s %-30s points %7d vertices %7d tets %8d  %.2f s"
                      % (status, name, npts, nv, nt, time.monotonic() - t0), flush=True)
            except (RuntimeError, OSError, subprocess.TimeoutExpired) as e:
                out = ["  FAIL %s" % e]
                print("FAIL %-30s" % name, flush=True)
            for line in out:
                print(line, flush=True)
            failed += bool(out)
    print("%d families, %d failed (%s)" % (len(names), failed,
                                           "CGAL vs gigatet" if args.gtet else "CGAL only"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
