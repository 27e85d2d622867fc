#!/usr/bin/env python3
"""gappa_gen.py -- writes the Gappa proof of a semi-static filter from the C code it certifies.

The filter's straight-line code is read from src/pred/filter.h (the `const double v = expr;`
statements of one `static inline int pred_*_filter(...)` function, up to `det`), so the proof is
always about the evaluation order that ships.  Every binary + - * of the C code is one rounding.

Model (proofs/filters.md gives the argument for each point):
  * Units.  A translated coordinate (p[i] - q[i]) of axis i has unit X, Y or Z (the maxima of the
    computed translated coordinates); a product has the product unit; a sum of terms with
    different units (x^2 + y^2 in insphere) is counted in the common unit where every mismatched
    axis is replaced by M = max(X, Y, Z), each term multiplied by a ratio r in [0, 1]
    (e.g. X^2/M^2).  Every quantity is normalised by its unit: the normalised computed
    translated coordinates t_* range over [-1, 1].
  * Translation.  The exact difference is t*(1 + e), |e| <= u = 2^-53 (|fl(s)-s| <= u|fl(s)| in
    round-to-nearest; an underflowing difference is exact).
  * Rounding of a product: fl(ab) = ab(1 + d) + g, |d| <= u, |g| <= 2^-1075 (Flocq's
    error_N_FLT); normalised, |g|/unit <= 2^-1075 / LO^degree by the guard min(X,Y,Z) >= LO.
    Rounding of a sum: fl(a+b) = (a+b)(1 + d), |d| <= u (an underflowing sum is exact).
  * Goal 1: an enclosure of (computed det - exact det) / unit(det), with hints that split the
    error along the evaluation (ca*cb - ea*eb = ca*(cb - eb) + (ca - ea)*eb, etc.).
  * Goal 2: the relative error of the evaluation of eps = ((C*X)*Y)*Z..., in binary64 with
    X, Y, Z, M in [1, 2] (scaling by powers of two is exact there: the guards exclude
    underflow and overflow of eps).
proofs/check then verifies, in exact rationals: goal1.hi <= C * (1 + goal2.lo), i.e.
|det~ - det| <= eps~, which is what the filter's decision `|det~| > eps~` needs.

Usage: gappa_gen.py FILTER_H FUNCTION_NAME OUT.g   (proofs/check calls gappa_text directly)
"""
import ast
import re
import sys
from fractions import Fraction as F


def function_body(text, fname):
    i = text.index(fname + "(")
    j = text.index("{", i)
    depth, k = 0, j
    while True:
        if text[k] == "{":
            depth += 1
        elif text[k] == "}":
            depth -= 1
            if depth == 0:
                return text[j + 1:k]
        k += 1


def split_top(s, sep=","):
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        if ch == sep and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    out.append(cur)
    return out


def statements(body):
    """(name, C expression) for each `const double name = expr` of the body, in order."""
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    out = []
    for stmt in body.split(";"):
        stmt = " ".join(stmt.split())
        if not stmt.startswith("const double "):
            continue
        for decl in split_top(stmt[len("const double "):]):
            name, expr = decl.split("=", 1)
            out.append((name.strip(), expr.strip()))
    return out


AXES = "XYZ"


class Unit:
    """A monomial X^a Y^b Z^c M^m, as a tuple (a, b, c, m)."""

    @staticmethod
    def mul(u, v):
        return tuple(x + y for x, y in zip(u, v))

    @staticmethod
    def deg(u):
        return sum(u)

    @staticmethod
    def common(u, v):
        w = tuple(min(x, y) for x, y in zip(u[:3], v[:3]))
        return w + (Unit.deg(u) - sum(w),)

    @staticmethod
    def name(u):
        s = "".join(f"{n}{e if e > 1 else ''}" for n, e in zip("XYZM", u) if e)
        return s or "1"


class Model:
    def __init__(s, lo):
        s.lo = lo            # guard: every axis maximum >= lo (a power of two)
        s.defs = []          # Gappa definitions, in order
        s.hyps = []          # hypotheses
        s.hints = []         # rewriting hints
        s.vars = {}          # C name -> node
        s.n = 0
        s.ratios = {}

    def fresh(s, base):
        s.n += 1
        return f"{base}{s.n}"

    # a node is (computed Gappa name, exact Gappa name, unit)
    def translation(s, axis, tag):
        t, e = f"t_{tag}", f"e_{tag}"
        s.hyps += [f"{t} in [-1, 1]", f"{e} in [-1b-53, 1b-53]"]
        c, x = t, f"x_{tag}"
        s.defs += [f"{x} = {t} + {t} * {e};"]
        s.hints.append(f"{c} - {x} -> -({t} * {e});")
        u = [0, 0, 0, 0]
        u[axis] = 1
        return (c, x, tuple(u))

    def convert(s, node, unit):
        c, x, u = node
        if u == unit:
            return node
        rname = f"r_{Unit.name(u)}_{Unit.name(unit)}"
        if rname not in s.ratios:
            s.ratios[rname] = True
            s.hyps.append(f"{rname} in [0, 1]")
        tag = s.fresh("k")
        c2, x2 = f"c_{tag}", f"x_{tag}"
        s.defs += [f"{c2} = {rname} * {c};", f"{x2} = {rname} * {x};"]
        s.hints.append(f"{c2} - {x2} -> {rname} * ({c} - {x});")
        return (c2, x2, unit)

    def binop(s, op, a, b, tag):
        if op == "*":
            unit = Unit.mul(a[2], b[2])
        else:
            unit = Unit.common(a[2], b[2])
            a, b = s.convert(a, unit), s.convert(b, unit)
        ca, xa, _ = a
        cb, xb, _ = b
        o, c, x, d = f"o_{tag}", f"c_{tag}", f"x_{tag}", f"d_{tag}"
        s.hyps.append(f"{d} in [-1b-53, 1b-53]")
        s.defs.append(f"{o} = {ca} {op} {cb};")
        s.defs.append(f"{x} = {xa} {op} {xb};")
        if op == "*":
            g = f"g_{tag}"
            # |g| <= 2^-1075 / unit, unit >= lo^degree
            k = -1075 - Unit.deg(unit) * s.lo
            s.hyps.append(f"{g} in [-1b{k}, 1b{k}]")
            s.defs.append(f"{c} = {o} + {o} * {d} + {g};")
            s.hints.append(f"{c} - {x} -> ({o} - {x}) + {o} * {d} + {g};")
            # o - x = ca*(cb - xb) + (ca - xa)*xb is Gappa's own rule for a product of two
            # approximations: no hint (an explicit one only widens the search)
        else:
            s.defs.append(f"{c} = {o} + {o} * {d};")
            s.hints.append(f"{c} - {x} -> ({o} - {x}) + {o} * {d};")
            s.hints.append(f"{o} - {x} -> ({ca} - {xa}) {op} ({cb} - {xb});")
        return (c, x, unit)

    def expr(s, node, name):
        if isinstance(node, ast.Name):
            return s.vars[node.id]
        if isinstance(node, ast.BinOp):
            # a translation p[i] - q[i] of two input coordinates
            if (isinstance(node.op, ast.Sub) and isinstance(node.left, ast.Subscript)
                    and isinstance(node.right, ast.Subscript)):
                i = node.left.slice.value
                j = node.right.slice.value
                assert i == j, "translation mixes axes"
                return s.translation(i, name)
            ops = {ast.Mult: "*", ast.Add: "+", ast.Sub: "-"}
            op = ops[type(node.op)]
            a = s.expr(node.left, None)
            b = s.expr(node.right, None)
            return s.binop(op, a, b, name or s.fresh("n"))
        raise ValueError(f"unsupported C expression: {ast.dump(node)}")


def log2_exact(v):
    f = F(v)
    k = 0
    while f > 1:
        f /= 2
        k += 1
    while f < 1:
        f *= 2
        k -= 1
    assert f == 1, "guard is not a power of two"
    return k


def generate(text, fname, lo_name, eps_name):
    body = function_body(text, fname)
    defines = dict(re.findall(r"#define\s+(\w+)\s+(\S+)", text))
    lo = float.fromhex(defines[lo_name])
    m = Model(log2_exact(lo))
    eps_expr = None
    for name, cexpr in statements(body):
        if "det" in m.vars and name != "eps":
            continue          # nothing after det but eps matters
        if "pred_" in cexpr:
            continue          # the maxima and guards: not part of the error analysis
        if name == "eps":
            eps_expr = cexpr
            continue
        m.vars[name] = m.expr(ast.parse(cexpr, mode="eval").body, name)
    det = m.vars["det"]
    # eps in binary64: C * X * Y * Z (* M * M), each factor in [1, 2]
    eps_py = ast.parse(eps_expr.replace(eps_name, "C"), mode="eval").body
    factors = []

    def eps_g(node):
        if isinstance(node, ast.Name):
            if node.id != "C":
                factors.append(node.id)
                return f"f{node.id}"
            return "C"
        assert isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult)
        return f"rnd({eps_g(node.left)} * {eps_g(node.right)})"
    eps_rounded = eps_g(eps_py)
    eps_exact = " * ".join(["C"] + [f"f{v}" for v in factors])
    return m, det, eps_rounded, eps_exact, sorted(set(factors)), lo


def render(fname, m, det, eps_rounded, eps_exact, factors):
    c, x, unit = det
    L = []
    short = fname[len("pred_"):-len("_filter")]
    L.append(f"# {short}.g -- GENERATED by proofs/gappa_gen.py from {fname} in")
    L.append("# src/pred/filter.h; do not edit (proofs/check regenerates it and fails if it differs).")
    L.append(f"# Goal 1: (computed det - exact det) / {Unit.name(unit)}, normalised model of")
    L.append("# proofs/filters.md (t_* translated coordinates / their axis maximum, e_* translation")
    L.append("# errors, d_* relative rounding errors, g_* underflow of products given the guard")
    L.append(f"# min(X,Y,Z) >= 2^{m.lo}, r_* ratios of units <= 1).")
    L.append("# Goal 2: relative error of eps = fl(C*...) in binary64, factors in [1,2].")
    L.append("#@ -Eprecision=120")
    L.append("@rnd = float<ieee_64, ne>;")
    L.append("C = rnd(Cr);  # the shipped constant: any double in [2^-60, 1] (goal 2 is the same)")
    for v in factors:
        L.append(f"f{v} = rnd(F{v});")
    L.append(f"epsc = {eps_rounded};")
    L.append(f"epsx = {eps_exact};")
    L += m.defs
    hyps = m.hyps + [f"f{v} in [1, 2]" for v in factors] + ["C in [1b-60, 1]"]
    L.append("{ " + "\n  /\\ ".join(hyps))
    L.append(f"  -> {c} - {x} in ? /\\ epsc -/ epsx in ? }}")
    L += m.hints
    return "\n".join(L) + "\n"


def filters(text):
    """Names of the pred_*_filter functions defined in a header."""
    return re.findall(r"static inline int (pred_\w+_filter)\(", text)


def spec(text, fname):
    """(guard constant, filter constant) named in the filter's body."""
    body = function_body(text, fname)
    lo = re.search(r"lo\s*>=\s*(PRED_\w+)", body).group(1)
    eps = re.search(r"const double eps\s*=([^;]*);", body).group(1)
    c = re.search(r"(PRED_\w+_C)\b", eps).group(1)
    return lo, c


def gappa_text(text, fname):
    lo_name, c_name = spec(text, fname)
    m, det, er, ex, factors, _ = generate(text, fname, lo_name, c_name)
    return render(fname, m, det, er, ex, factors)


def main():
    filter_h, fname, out = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(out, "w") as fh:
        fh.write(gappa_text(open(filter_h).read(), fname))


if __name__ == "__main__":
    main()
