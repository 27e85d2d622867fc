/* check_filter.c -- interval-arithmetic front end of the checker's predicates: decide the sign in
 * doubles when an enclosing interval proves it, else ask the exact GMP oracle.
 *
 * Why it is exact.  Each operation is evaluated in binary64 round-to-nearest (the build's
 * assumption, FLT_EVAL_METHOD == 0, no contraction) and its result f widened to its neighbours
 * [pred(f), succ(f)].  For any real t with RN(t) = f finite, t lies strictly between pred(f)
 * and succ(f) (t is nearer to f than to either neighbour), subnormal results included; for an
 * overflow f = +-inf the bound on the infinite side is inf and the other one is +-DBL_MAX,
 * still valid.  An interval operation applies the operation to the bounds (for a product: all
 * four bound products, min and max) and widens each bound outward, so the exact value of every
 * subexpression stays inside its interval.  Invalid operations (inf - inf, 0 * inf) give NaN,
 * which decides nothing: a sign is returned only when lo > 0 or hi < 0.  The polynomials are
 * the oracle's, term for term, so a decided sign is the oracle's sign; an undecided one (zero,
 * or too close to call) is the oracle's answer itself.  The perturbed predicates equal the plain
 * sign whenever that is nonzero, so the filter serves them too.  tests/test_check_filter.c
 * compares every filtered sign with the oracle on adversarial data.
 *
 * This is independent of src/pred/ (whose filters are semi-static error bounds); it only makes
 * the checker fast enough for millions of tets (GTET_CHECK_NO_FILTER turns it off).
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

static iv iv_add(iv a, iv b) { return (iv){pred(a.lo + b.lo), succ(a.hi + b.hi)}; }

static iv iv_sub(iv a, iv b) { return (iv){pred(a.lo - b.hi), succ(a.hi - b.lo)}; }

static iv iv_mul(iv a, iv b)
{
    double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    double mn = p[0], mx = p[0];
    for (int i = 0; i < 4; i++) {
        if (isnan(p[i])) return (iv){NAN, NAN};
        if (p[i] < mn) mn = p[i];
        if (p[i] > mx) mx = p[i];
    }
    return (iv){pred(mn), succ(mx)};
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

int chk_orient3d(const chk_ctx *c, const double *a, const double *b, const double *cc,
                 const double *d)
{
    int s = (c->flags & GTET_CHECK_NO_FILTER) ? 0 : filter_orient3d(a, b, cc, d);
    return s ? s : orc_orient3d(a, b, cc, d);
}

int chk_insphere_sos(const chk_ctx *c, const double *a, const double *b, const double *cc,
                     const double *d, const double *e)
{
    int s = (c->flags & GTET_CHECK_NO_FILTER) ? 0 : filter_insphere(a, b, cc, d, e);
    return s ? s : orc_insphere_sos(a, b, cc, d, e);
}

int chk_ghost_conflict(const chk_ctx *c, const double *a, const double *b, const double *cc,
                       const double *e)
{
    /* a nonzero orient3d(a,b,c,e) is the hull rule's answer */
    int s = (c->flags & GTET_CHECK_NO_FILTER) ? 0 : filter_orient3d(a, b, cc, e);
    return s ? s : orc_ghost_conflict(a, b, cc, e);
}
