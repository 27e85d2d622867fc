#!/usr/bin/env python3
"""filter_bound.py -- derives the filter constants of filter.h by exact rational propagation.

Each computed quantity carries (mag, err): |computed| <= mag * U and |computed - exact| <= err * U
in the units U named in filter.h (XYZ for orient3d, XYZ*M^2 for insphere).  Inputs are the
translated coordinates: mag 1, err u (rounding of the translation).  A rounded product or sum of
exact value s has error <= u*|s| and magnitude <= |s|*(1+u).  The constant is
E / (1-u)^k * (1 + 2^-40) rounded up to a double, k = roundings in the evaluation of eps.
Run: python3 src/pred/filter_bound.py
"""
from fractions import Fraction as F
import math

u = F(1, 2**53)


class B:
    def __init__(s, mag, err):
        s.mag, s.err = mag, err


def inp():
    return B(F(1), u)


def mul(a, b):
    ex = a.mag * b.mag
    return B(ex * (1 + u), a.mag * b.err + (b.mag + b.err) * a.err + u * ex)


def add(a, b):
    ex = a.mag + b.mag
    return B(ex * (1 + u), a.err + b.err + u * ex)


sub = add


def up(x):
    d = float(x)
    while F(d) < x:
        d = math.nextafter(d, math.inf)
    return d


def report(name, det, k):
    c = up(det.err / (1 - u)**k * (1 + F(1, 2**40)))
    print(f"{name}: E = {float(det.err / u)!r} u, |det| <= {float(det.mag)!r}, "
          f"C = {c!r} ({float(F(c) / u)!r} u)")


x = inp()
# orient3d: m = q.r - q.r ; det = (p*m1 + p*m2) + p*m3
m = sub(mul(x, x), mul(x, x))
t = mul(x, m)
report("orient3d", add(add(t, t), t), 3)
# insphere: 2x2 minors, 3x3 minors, lifts, det = (w*abc - w*abc) + (w*abc - w*abc)
xy = sub(mul(x, x), mul(x, x))
abc = add(sub(mul(x, xy), mul(x, xy)), mul(x, xy))
w = add(add(mul(x, x), mul(x, x)), mul(x, x))
report("insphere", add(sub(mul(w, abc), mul(w, abc)), sub(mul(w, abc), mul(w, abc))), 5)
