/* check_filter.c -- interval-arithmetic front end of the checker's predicates: decide the sign in
 * doubles when an enclosing interval proves it, else ask the exact GMP oracle.
 *
 * Why it is exact.  Each operation is evaluated in binary64 round-to-nearest (the build's
 * assumption, FLT_EVAL_METHOD == 0, no contraction) and its result f widened to its neighbours
 * [pred(f), succ(f)].  For any real t with RN(t) = f finite, t lies strictly between pred(f)
 * and succ(f) (t is nearer to f than to either neighbour), subnormal results included; for an
 * overflow f = +-inf the bound on the infinite side is inf and the other one is +-DBL_MAX,
 * still valid.  An interval operation applies the operation to the bounds (for a product: all
 * four bound products, min and max) and widens each bound outward (except where the result is
 * exactly 0, see down() and iv_mul()), so the exact value of every subexpression stays inside
 * its interval.  Invalid operations (inf - inf, 0 * inf) give NaN,
 * which decides nothing: a sign is returned only when lo > 0 or hi < 0.  The polynomials are
 * the oracle's, term for term, so a decided sign is the oracle's sign; an undecided one (zero,
 * or too close to call) is the oracle's answer itself.  The perturbed predicates equal the plain
 * sign whenever that is nonzero, so the filter serves them too.  tests/test_check_filter.c
 * compares every filtered sign with the oracle on adversarial data.
 *
 * This is independent of src/pred/ (whose filters are semi-static error bounds); it only makes
 * the checker fast enough for millions of tets (GTET_CHECK_NO_FILTER turns it off).
 *
 * A cheaper first stage (fast_orient3d, fast_insphere) runs before the intervals: the same
 * determinant in plain doubles, d, and its "permanent" p, the same expression tree evaluated on
 * the absolute values of the leaves with every - turned into +.  Why |d - det| <= 2^-49 p:
 *   - Range guard.  The leaves are the computed differences x = fl(q_j - e_j).  The stage runs
 *     only when every leaf is 0 or 2^-120 <= |x| <= 2^120 (NaN and inf fail the test).  Then
 *     every operation obeys fl(s op t) = (s op t)(1 + delta), |delta| <= u = 2^-53: nothing
 *     overflows (every value is below 2^700), a sum or difference whose result is subnormal is
 *     exact, and no exact nonzero product is subnormal.  For the products, use that a double
 *     of magnitude >= 2^m is a multiple of 2^(m-52), so a nonzero sum of two doubles of
 *     magnitude >= 2^m is >= 2^(m-52): the 2x2 products are 0 or >= 2^-240, the 2x2 minors
 *     >= 2^-292, their products with a leaf >= 2^-412, the 3x3 minors (two more additions)
 *     >= 2^-516, the lifts (sums of squares, no cancellation) >= 2^-240, lift * minor >= 2^-756.
 *   - Error.  Expanding the tree, the computed d is the sum of its signed monomials, each
 *     multiplied by at most k factors (1 + delta) (k = the tree's depth, leaf subtraction
 *     included: k <= 10 here), while det is the same sum with the factors 1.  So
 *     |d - det| <= ((1+u)^k - 1) P, where P is the sum of the monomials' absolute values, i.e.
 *     the permanent of the exact leaves.  The computed p is P times at most k factors (1 + delta)
 *     (leaves included, no cancellation), so P <= p / (1-u)^k, and
 *     |d - det| <= ((1+u)^10 - 1) / (1-u)^10 p < 11u p < 2^-49 p.
 *   - Decision.  The stage returns sign(d) only when |d| > 2^-45 p (the product by 2^-45 is
 *     exact in this range); then |det| >= |d| - 2^-49 p > 0 and det has the sign of d.
 *     Otherwise (exact zeros of grids, near-degenerate tuples) the oracle decides: the
 *     intervals would rarely do better there, and on grids they cost more than the oracle.
 *     The interval stage runs only when the range guard fails (fast_* return 2).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "../oracle/oracle.h"
#include "check_internal.h"

typedef struct iv {
    double lo, hi;
} iv;

/* pred(x) = nextafter(x, -inf), inlined: the adjacent binary64 toward -inf.  Doubles of one
 * sign are ordered like their bit patterns read as integers (magnitude order), so one step of
 * the integer is one step of the double: down for x > 0 (+inf -> DBL_MAX, the smallest
 * subnormal -> +0), up in magnitude for x < 0 (-DBL_MAX -> -inf).  Zeros of either sign step to
 * the negative smallest subnormal; -inf and NaN stay. */
static double pred(double x)
{
    if (isnan(x) || x == -INFINITY) return x;
    if (x == 0.0) return -0x1p-1074;
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    b = x > 0 ? b - 1 : b + 1;
    memcpy(&x, &b, sizeof x);
    return x;
}

static double succ(double x) { return -pred(-x); }

static iv iv_pt(double x) { return (iv){x, x}; }

/* A sum or difference of two doubles that rounds to 0 is exactly 0 (the exact result is a
 * multiple of 2^-1074, and every such multiple below 2^-1022 is a double), so a 0 bound is kept
 * as is: no subnormal bounds (slow on x86) for the exact zeros of grid inputs. */
static double down(double f) { return f == 0.0 ? 0.0 : pred(f); }
static double up(double f) { return f == 0.0 ? 0.0 : succ(f); }

static iv iv_add(iv a, iv b) { return (iv){down(a.lo + b.lo), up(a.hi + b.hi)}; }

static iv iv_sub(iv a, iv b) { return (iv){down(a.lo - b.hi), up(a.hi - b.lo)}; }

/* x*y rounded, widened down / up, unless a factor is 0 (then the product is exactly 0). */
static double mul_down(double x, double y) { return x == 0.0 || y == 0.0 ? 0.0 : pred(x * y); }
static double mul_up(double x, double y) { return x == 0.0 || y == 0.0 ? 0.0 : succ(x * y); }

/* [a]*[b]: when both signs are known the bounds are two specific corner products (products of
 * same-signed factors are monotone in each factor); otherwise the min and max of all four.
 * A NaN anywhere (inf * 0, NaN inputs fall to the general case) makes the result NaN. */
static iv iv_mul(iv a, iv b)
{
    iv r;
    if (a.lo >= 0 && b.lo >= 0)
        r = (iv){mul_down(a.lo, b.lo), mul_up(a.hi, b.hi)};
    else if (a.lo >= 0 && b.hi <= 0)
        r = (iv){mul_down(a.hi, b.lo), mul_up(a.lo, b.hi)};
    else if (a.hi <= 0 && b.lo >= 0)
        r = (iv){mul_down(a.lo, b.hi), mul_up(a.hi, b.lo)};
    else if (a.hi <= 0 && b.hi <= 0)
        r = (iv){mul_down(a.hi, b.hi), mul_up(a.lo, b.lo)};
    else {
        const double x[4] = {a.lo, a.lo, a.hi, a.hi}, y[4] = {b.lo, b.hi, b.lo, b.hi};
        r = (iv){INFINITY, -INFINITY};
        for (int i = 0; i < 4; i++) {
            if (isnan(x[i] * y[i])) return (iv){NAN, NAN};
            double pl = mul_down(x[i], y[i]), ph = mul_up(x[i], y[i]);
            if (pl < r.lo) r.lo = pl;
            if (ph > r.hi) r.hi = ph;
        }
    }
    if (isnan(r.lo) || isnan(r.hi)) return (iv){NAN, NAN};
    return r;
}

/* +1 / -1 when the interval proves the sign, 0 when it does not (zero inside, or NaN). */
static int iv_sign(iv a) { return a.lo > 0 ? 1 : (a.hi < 0 ? -1 : 0); }

/* det of the 3x3 rows u, v, w: u0 (v1 w2 - v2 w1) - u1 (v0 w2 - v2 w0) + u2 (v0 w1 - v1 w0) */
static iv iv_det3(const iv u[3], const iv v[3], const iv w[3])
{
    iv m0 = iv_sub(iv_mul(v[1], w[2]), iv_mul(v[2], w[1]));
    iv m1 = iv_sub(iv_mul(v[0], w[2]), iv_mul(v[2], w[0]));
    iv m2 = iv_sub(iv_mul(v[0], w[1]), iv_mul(v[1], w[0]));
    return iv_add(iv_sub(iv_mul(u[0], m0), iv_mul(u[1], m1)), iv_mul(u[2], m2));
}

static int filter_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    iv u[3], v[3], w[3];
    for (int j = 0; j < 3; j++) {
        u[j] = iv_sub(iv_pt(b[j]), iv_pt(a[j]));
        v[j] = iv_sub(iv_pt(c[j]), iv_pt(a[j]));
        w[j] = iv_sub(iv_pt(d[j]), iv_pt(a[j]));
    }
    return iv_sign(iv_det3(u, v, w));
}

/* -sign det[x - e, |x - e|^2] (rows x = a, b, c, d), expanded along the lifted column like
 * the oracle's det4: sum over rows i of (-1)^(i+3) lift_i * minor_i. */
static int filter_insphere(const double *a, const double *b, const double *c, const double *d,
                           const double *e)
{
    const double *p[4] = {a, b, c, d};
    iv r[4][3], lift[4];
    for (int i = 0; i < 4; i++) {
        lift[i] = iv_pt(0.0);
        for (int j = 0; j < 3; j++) {
            r[i][j] = iv_sub(iv_pt(p[i][j]), iv_pt(e[j]));
            lift[i] = iv_add(lift[i], iv_mul(r[i][j], r[i][j]));
        }
    }
    iv det = iv_pt(0.0);
    for (int i = 0; i < 4; i++) {
        const iv *rows[3];
        int k = 0;
        for (int row = 0; row < 4; row++)
            if (row != i) rows[k++] = r[row];
        iv t = iv_mul(lift[i], iv_det3(rows[0], rows[1], rows[2]));
        det = (i + 3) % 2 == 0 ? iv_add(det, t) : iv_sub(det, t);
    }
    return -iv_sign(det);
}

/* The range guard of the double stage: x is 0 or 2^-120 <= |x| <= 2^120 (false for NaN, inf). */
static int in_range(double x)
{
    double a = fabs(x);
    return x == 0.0 || (a >= 0x1p-120 && a <= 0x1p120);
}

/* det3 of rows u, v, w and its permanent (same tree, absolute values, all additions). */
static double fdet3(const double u[3], const double v[3], const double w[3], double *perm,
                    const double au[3], const double av[3], const double aw[3])
{
    double m0 = v[1] * w[2] - v[2] * w[1];
    double m1 = v[0] * w[2] - v[2] * w[0];
    double m2 = v[0] * w[1] - v[1] * w[0];
    double p0 = av[1] * aw[2] + av[2] * aw[1];
    double p1 = av[0] * aw[2] + av[2] * aw[0];
    double p2 = av[0] * aw[1] + av[1] * aw[0];
    *perm = au[0] * p0 + au[1] * p1 + au[2] * p2;
    return u[0] * m0 - u[1] * m1 + u[2] * m2;
}

/* sign(d) when |d| > 2^-45 p proves it (see the top), else 0 (the fast_* functions return 2
 * when the range guard fails). */
static int fast_sign(double d, double p)
{
    double b = p * 0x1p-45;
    return d > b ? 1 : (d < -b ? -1 : 0);
}

/* Depth: leaf 1, product 2, difference 3, product 4, two additions 6. */
static int fast_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3], au[3], av[3], aw[3];
    int ok = 1;
    for (int j = 0; j < 3; j++) {
        u[j] = b[j] - a[j];
        v[j] = c[j] - a[j];
        w[j] = d[j] - a[j];
        ok &= in_range(u[j]) & in_range(v[j]) & in_range(w[j]);
        au[j] = fabs(u[j]);
        av[j] = fabs(v[j]);
        aw[j] = fabs(w[j]);
    }
    if (!ok) return 2;
    double p, det = fdet3(u, v, w, &p, au, av, aw);
    return fast_sign(det, p);
}

/* -sign det[x - e, |x - e|^2], as filter_insphere.  Depth: the lifts 4 (leaf, square, two
 * additions), the 3x3 minors 6, their products with the lifts 7, three additions 10. */
static int fast_insphere(const double *a, const double *b, const double *c, const double *d,
                         const double *e)
{
    const double *p[4] = {a, b, c, d};
    double r[4][3], ar[4][3], lift[4];
    int ok = 1;
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 3; j++) {
            r[i][j] = p[i][j] - e[j];
            ok &= in_range(r[i][j]);
            ar[i][j] = fabs(r[i][j]);
        }
        lift[i] = r[i][0] * r[i][0] + r[i][1] * r[i][1] + r[i][2] * r[i][2];
    }
    if (!ok) return 2;
    double pm[4], m[4];
    m[0] = fdet3(r[1], r[2], r[3], &pm[0], ar[1], ar[2], ar[3]);
    m[1] = fdet3(r[0], r[2], r[3], &pm[1], ar[0], ar[2], ar[3]);
    m[2] = fdet3(r[0], r[1], r[3], &pm[2], ar[0], ar[1], ar[3]);
    m[3] = fdet3(r[0], r[1], r[2], &pm[3], ar[0], ar[1], ar[2]);
    /* sum over rows i of (-1)^(i+3) lift_i minor_i, as filter_insphere */
    double det = -lift[0] * m[0] + lift[1] * m[1] - lift[2] * m[2] + lift[3] * m[3];
    double perm = lift[0] * pm[0] + lift[1] * pm[1] + lift[2] * pm[2] + lift[3] * pm[3];
    return -fast_sign(det, perm);
}

int chk_orient3d(const chk_ctx *c, const double *a, const double *b, const double *cc,
                 const double *d)
{
    if (c->flags & GTET_CHECK_NO_FILTER) return orc_orient3d(a, b, cc, d);
    int s = fast_orient3d(a, b, cc, d);
    if (s == 2) s = filter_orient3d(a, b, cc, d);
    return s ? s : orc_orient3d(a, b, cc, d);
}

/* The filters' sign, else the oracle's exact answer `exact` (plain or perturbed: both equal
 * the plain sign whenever it is nonzero). */
static int insphere_with(const chk_ctx *c, const double *a, const double *b, const double *cc,
                         const double *d, const double *e,
                         int (*exact)(const double *, const double *, const double *,
                                      const double *, const double *))
{
    if (c->flags & GTET_CHECK_NO_FILTER) return exact(a, b, cc, d, e);
    int s = fast_insphere(a, b, cc, d, e);
    if (s == 2) s = filter_insphere(a, b, cc, d, e);
    return s ? s : exact(a, b, cc, d, e);
}

int chk_insphere(const chk_ctx *c, const double *a, const double *b, const double *cc,
                 const double *d, const double *e)
{
    return insphere_with(c, a, b, cc, d, e, orc_insphere);
}

int chk_insphere_sos(const chk_ctx *c, const double *a, const double *b, const double *cc,
                     const double *d, const double *e)
{
    return insphere_with(c, a, b, cc, d, e, orc_insphere_sos);
}

int chk_ghost_conflict(const chk_ctx *c, const double *a, const double *b, const double *cc,
                       const double *e)
{
    /* a nonzero orient3d(a,b,c,e) is the hull rule's answer */
    if (c->flags & GTET_CHECK_NO_FILTER) return orc_ghost_conflict(a, b, cc, e);
    int s = fast_orient3d(a, b, cc, e);
    if (s == 2) s = filter_orient3d(a, b, cc, e);
    return s ? s : orc_ghost_conflict(a, b, cc, e);
}
