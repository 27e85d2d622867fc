/* expansion.h -- exact floating-point expansion arithmetic (Shewchuk 1997, our own code).
 *
 * An expansion is an array e[0..n-1] of doubles whose exact sum is the value represented,
 * ordered by increasing magnitude, with no zero components and strongly nonoverlapping
 * (J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
 * Predicates", DCG 18, 1997: Theorems 6-7 (Two-Sum), 18 (Two-Product), 13 (Fast-Expansion-Sum),
 * 19 (Scale-Expansion)).  The sign of an expansion is the sign of its last (largest) component,
 * 0 when it is empty.
 *
 * Assumptions (fpenv.h): binary64, round to nearest even, no FMA contraction, no extended
 * precision.  Additionally every product formed must neither overflow nor lose bits to
 * underflow: callers guarantee it by keeping all inputs in a magnitude band (exact_band in
 * pred_internal.h): Dekker's split and the product tail are exact when every partial product
 * is a multiple of 2^-1074 that fits in 53 bits and stays below 2^996.
 */
#ifndef GTET_PRED_EXPANSION_H
#define GTET_PRED_EXPANSION_H

#include "fpenv.h"

/* x + y == a + b exactly, x = fl(a + b) (Knuth's Two-Sum: no precondition on magnitudes). */
static inline void exp_two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    double bv = s - a;
    double av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* x + y == a + b exactly, requires |a| >= |b| or a == 0 (Dekker's Fast-Two-Sum). */
static inline void exp_fast_two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    *x = s;
    *y = b - (s - a);
}

/* a == hi + lo with hi, lo of at most 26 significant bits each (Dekker's split;
 * 134217729 = 2^27 + 1). */
static inline void exp_split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a;
    double big = c - a;
    double h = c - big;
    *hi = h;
    *lo = a - h;
}

/* x + y == a * b exactly, x = fl(a * b) (Dekker / Veltkamp Two-Product). */
static inline void exp_two_prod(double a, double b, double *x, double *y)
{
    double p = a * b, ah, al, bh, bl;
    exp_split(a, &ah, &al);
    exp_split(b, &bh, &bl);
    double e1 = p - ah * bh;
    double e2 = e1 - al * bh;
    double e3 = e2 - ah * bl;
    *x = p;
    *y = al * bl - e3;
}

/* h = a*b - c*d as an expansion of at most 4 components; returns its length. */
int exp_two_two_diff(double a, double b, double c, double d, double *h);

/* h = e + f (Fast-Expansion-Sum with zero elimination); h must not alias e or f.
 * Length <= elen + flen. */
int exp_sum(int elen, const double *e, int flen, const double *f, double *h);

/* h = e * b (Scale-Expansion with zero elimination); length <= 2 * elen.  h != e. */
int exp_scale(int elen, const double *e, double b, double *h);

/* h = e * f; length <= 2 * elen * flen.  tmp must hold 2*elen*flen doubles and tmp2
 * 2*elen doubles; h, tmp, tmp2, e, f pairwise distinct. */
int exp_mul(int elen, const double *e, int flen, const double *f, double *h, double *tmp,
            double *tmp2);

/* h = e compressed (Shewchuk's Compress, section 2.8): same value, nonadjacent, usually far
 * fewer components (a product's many tiny error terms merge).  h may alias e. */
int exp_compress(int elen, const double *e, double *h);

/* e = -e in place. */
static inline void exp_negate(int elen, double *e)
{
    for (int i = 0; i < elen; i++) e[i] = -e[i];
}

static inline int exp_sign(int elen, const double *e)
{
    if (elen == 0) return 0;
    return e[elen - 1] > 0 ? 1 : -1;
}

#endif
