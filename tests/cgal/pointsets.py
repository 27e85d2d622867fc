#!/usr/bin/env python3
"""pointsets.py -- the point sets of the CGAL differential tests and of bench/.

Deliberately independent of gigatet's own generator (the CLI's `generate`), so a bug there
cannot hide a bug in the kernel.  Every coordinate is built exactly: integers, dyadic
rationals, Python's Mersenne twister (53-bit random() values), and scalings by powers of two
(math.ldexp), all exact in binary64; so a family is the same bit pattern on every run and
host.  Degenerate families put many points on one plane / circle / sphere so that orient3d and
insphere are exactly zero over and over and only the symbolic perturbation decides.

Library use: FAMILIES maps a name to a function(size_mode, rng) -> list of (x, y, z).
Command line (bench/run.sh):  pointsets.py KIND N [--seed S] -o FILE.{bin,xyz,node}
    KIND: uniform (N points in [0,1)^3), grid (N = side, side^3 integer points, shuffled),
    halfcube (N/2 points uniform in [0,1)^3 and N - N/2 in the cube [0.5, 0.501)^3: a dense
    cluster inside one Delaunay cell of a sparse set, NOTES.md Q3/E5) or mixed (N points
    uniform in [0,1)^3, each scaled by one of 10^-300, 10^-150, 1, 10^150, 10^300 at random:
    the mixed 10^+-300 scales of NOTES.md Q5); the same KIND N SEED gives the same points in
    every format.
"""
import argparse
import math
import random
import struct
import sys


def write_bin(path, pts):
    """Little-endian uint64 count, then x y z binary64 per point."""
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(pts)))
        flat = [c for p in pts for c in p]
        for i in range(0, len(flat), 3 << 16):  # chunks: bounded memory for struct
            chunk = flat[i:i + (3 << 16)]
            f.write(struct.pack("<%dd" % len(chunk), *chunk))


def write_xyz(path, pts):
    """Text with C99 hex floats: read back bit-exact by strtod."""
    with open(path, "w") as f:
        f.write("# x y z (hex floats)\n")
        for p in pts:
            f.write("%s %s %s\n" % tuple(float.hex(float(c)) for c in p))


def write_node(path, pts):
    """TetGen .node: "N 3 0 0", then "i x y z" with i from 1; %.17g reads back bit-exact."""
    with open(path, "w") as f:
        f.write("%d 3 0 0\n" % len(pts))
        for i in range(0, len(pts), 1 << 16):
            f.write("".join("%d %.17g %.17g %.17g\n" % (i + j + 1, p[0], p[1], p[2])
                            for j, p in enumerate(pts[i:i + (1 << 16)])))


def uniform(n, rng):
    return [(rng.random(), rng.random(), rng.random()) for _ in range(n)]


def grid(k, rng, dup_fraction=0.0):
    """k^3 integer points, shuffled, plus exact duplicates of a random fraction."""
    pts = [(float(x), float(y), float(z)) for x in range(k) for y in range(k) for z in range(k)]
    pts += [rng.choice(pts) for _ in range(int(dup_fraction * len(pts)))]
    rng.shuffle(pts)
    return pts


def cospherical(r2, rng, centre=False):
    """All integer points with x^2+y^2+z^2 = r2 (every 5 of them co-spherical)."""
    r = math.isqrt(r2)
    pts = []
    for x in range(-r, r + 1):
        for y in range(-r, r + 1):
            z2 = r2 - x * x - y * y
            if z2 < 0:
                continue
            z = math.isqrt(z2)
            if z * z == z2:
                pts.append((float(x), float(y), float(z)))
                if z:
                    pts.append((float(x), float(y), float(-z)))
    if centre:
        pts.append((0.0, 0.0, 0.0))
    rng.shuffle(pts)
    return pts


def cube_corners(centre):
    pts = [(float(x), float(y), float(z)) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    if centre:
        pts.append((0.5, 0.5, 0.5))
    return pts


def fcc(k, rng):
    """Face-centred cubic: integer points of [0,k)^3 with an even coordinate sum."""
    pts = [(float(x), float(y), float(z)) for x in range(k) for y in range(k) for z in range(k)
           if (x + y + z) % 2 == 0]
    rng.shuffle(pts)
    return pts


def bcc(k, rng):
    """Body-centred cubic: the grid [0,k)^3 plus the centres of its cubes."""
    pts = [(float(x), float(y), float(z)) for x in range(k) for y in range(k) for z in range(k)]
    pts += [(x + 0.5, y + 0.5, z + 0.5) for x in range(k - 1) for y in range(k - 1)
            for z in range(k - 1)]
    rng.shuffle(pts)
    return pts


def paraboloid(k, rng):
    """(x, y, x^2+y^2) on an integer grid: 4 lifted co-circular grid points are coplanar."""
    h = k // 2
    pts = [(float(x), float(y), float(x * x + y * y)) for x in range(-h, k - h)
           for y in range(-h, k - h)]
    rng.shuffle(pts)
    return pts


def plane_apex(k, height, rng):
    """A k x k integer grid in z = 0 (co-circular everywhere) and one apex above its middle."""
    pts = [(float(x), float(y), 0.0) for x in range(k) for y in range(k)]
    pts.append(((k - 1) / 2.0, (k - 1) / 2.0, height))
    rng.shuffle(pts)
    return pts


def scaled(pts, e):
    return [(math.ldexp(x, e), math.ldexp(y, e), math.ldexp(z, e)) for x, y, z in pts]


def signed_zeros(rng, k):
    """Grid {-1,0,1,..,k-2}^3 where each zero is -0.0 or +0.0 at random, with duplicates that
    differ only in the sign of a zero, so they must map to the first occurrence."""
    pts = []
    vals = list(range(-1, k - 1))
    for x in vals:
        for y in vals:
            for z in vals:
                pts.append(tuple(float(c) if c else rng.choice((0.0, -0.0)) for c in (x, y, z)))
    extra = []
    for _ in range(len(pts) // 3):
        p = rng.choice(pts)
        extra.append(tuple(-c if c == 0.0 else c for c in p))  # flips the zeros' signs only
    pts += extra
    rng.shuffle(pts)
    return pts


def uniform_dups(n, rng):
    pts = uniform(n, rng)
    pts += [rng.choice(pts) for _ in range(n // 3)]
    rng.shuffle(pts)
    return pts


def mixed_scales(n, rng):
    """A uniform set scaled by 2^-1000 together with a copy scaled by 2^1000: insphere terms
    span 2^-4000..2^4000, far outside double range, so only exact stages decide."""
    base = uniform(n, rng)
    pts = scaled(base, -1000) + scaled(base, 1000)
    rng.shuffle(pts)
    return pts


def halfcube(n, rng):
    """n//2 uniform in [0,1)^3, the rest uniform in [0.5, 0.501)^3, shuffled."""
    pts = uniform(n // 2, rng)
    pts += [(0.5 + 1e-3 * rng.random(), 0.5 + 1e-3 * rng.random(), 0.5 + 1e-3 * rng.random())
            for _ in range(n - n // 2)]
    rng.shuffle(pts)
    return pts


def mixed_decades(n, rng):
    """Uniform points, each scaled by 10^e, e in {-300, -150, 0, 150, 300} at random (each
    product one correctly rounded multiplication: the same bits on every host)."""
    scales = [10.0 ** e for e in (-300, -150, 0, 150, 300)]
    pts = []
    for _ in range(n):
        s = scales[rng.randrange(5)]
        pts.append((rng.random() * s, rng.random() * s, rng.random() * s))
    return pts


# name -> (function(small, rng) -> points).  `small` selects the sanitizer-sized variant.
FAMILIES = {
    "uniform_1k": lambda s, r: uniform(1000, r),
    "uniform_10k": lambda s, r: uniform(2000 if s else 10000, r),
    "uniform_100k": lambda s, r: uniform(5000 if s else 100000, r),
    "uniform_with_duplicates": lambda s, r: uniform_dups(1000 if s else 20000, r),
    "grid_10": lambda s, r: grid(6 if s else 10, r),
    "grid_20_duplicates": lambda s, r: grid(8 if s else 20, r, 0.25),
    "cospherical_r2_2025": lambda s, r: cospherical(625 if s else 2025, r),
    "cospherical_r2_21125_centre": lambda s, r: cospherical(2025 if s else 21125, r, True),
    "cube_corners": lambda s, r: cube_corners(False),
    "cube_corners_centre": lambda s, r: cube_corners(True),
    "fcc": lambda s, r: fcc(7 if s else 16, r),
    "bcc": lambda s, r: bcc(5 if s else 12, r),
    "paraboloid": lambda s, r: paraboloid(10 if s else 40, r),
    "plane_apex": lambda s, r: plane_apex(8 if s else 30, 1.0, r),
    "plane_denormal_apex": lambda s, r: plane_apex(8 if s else 30, math.ldexp(1.0, -1074), r),
    "uniform_tiny_2m1000": lambda s, r: scaled(uniform(1000 if s else 5000, r), -1000),
    "uniform_huge_2p1000": lambda s, r: scaled(uniform(1000 if s else 5000, r), 1000),
    "grid_huge_2p1000": lambda s, r: scaled(grid(6 if s else 10, r), 1000),
    "mixed_scales": lambda s, r: mixed_scales(500 if s else 3000, r),
    "signed_zeros_duplicates": lambda s, r: signed_zeros(r, 4 if s else 6),
}


def family(name, small=False, seed=1):
    return FAMILIES[name](small, random.Random("%s/%d" % (name, seed)))


def main(argv):
    ap = argparse.ArgumentParser(description="write a benchmark point set")
    ap.add_argument("kind", choices=["uniform", "grid", "halfcube", "mixed"])
    ap.add_argument("n", type=int, help="points, or the side length (grid)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("-o", dest="out", required=True)
    a = ap.parse_args(argv)
    rng = random.Random(a.seed)
    make = {"uniform": uniform, "grid": grid, "halfcube": halfcube, "mixed": mixed_decades}
    pts = make[a.kind](a.n, rng)
    if a.out.endswith(".xyz"):
        write_xyz(a.out, pts)
    elif a.out.endswith(".node"):
        write_node(a.out, pts)
    else:
        write_bin(a.out, pts)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
