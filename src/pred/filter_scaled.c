/* filter_scaled.c -- the semi-static filters on translations scaled by 2^s, for tuples whose
 * translated coordinates lie outside the window the constants are proved for (filter.h
 * guards: orient3d [2^-320, 2^340], insphere [2^-192, 2^200]) but spread over less than the
 * window: a cluster of points near 10^-300 or 10^300 (proofs/filters.md section 11).
 *
 * Why it is sound.  The filter's proof takes the computed translations x~ = fl(b - a) with
 * (R1) |x~ - x| <= u |x~| and bounds the rounding of the fixed evaluation order, provided the
 * maxima lie in the window.  Multiplying every x~ by 2^s gives 2^s x~, which satisfies (R1)
 * against 2^s x when 2^s x~ is computed exactly; these are the translations of the points
 * scaled by 2^s, whose orient3d / insphere determinant is 2^(3s) / 2^(5s) times the original:
 * the same sign.  The scaled translations are handed to the shipped filter as points with the
 * base point at the origin, so it evaluates exactly its own expression on them (o - 0 = o).
 * Exactness of the scaling: for s >= 0 every product x~ * 2^s is exact (the scaled maximum is
 * below 2^target, far from overflow); for s < 0 a product may underflow and round, so every
 * scaled value is multiplied back and compared with the original (scaling a double up by a
 * power of two is exact short of overflow, so a rounded product cannot come back equal); any
 * mismatch is "undecided".  Undecided answers (0) go on to the exact stages.
 */
#include <math.h>
#include <stddef.h>

#include "filter.h"

/* 1 when the per-axis maxima of the n / 3 translations t (x, y, z each) are all at least lo
 * and at most hi: the unscaled filter's window, already tried.  *max: the largest. */
static inline int in_window(const double *t, int n, double lo, double hi, double *max)
{
    double X = pred_fabs_(t[0]), Y = pred_fabs_(t[1]), Z = pred_fabs_(t[2]);
    for (int i = 3; i < n; i += 3) {
        X = pred_max_(X, pred_fabs_(t[i]));
        Y = pred_max_(Y, pred_fabs_(t[i + 1]));
        Z = pred_max_(Z, pred_fabs_(t[i + 2]));
    }
    *max = pred_max_(pred_max_(X, Y), Z);
    return pred_min_(pred_min_(X, Y), Z) >= lo && *max <= hi;
}

/* Scale n translations so that their maximum magnitude m is in [2^(target-1), 2^target); 0
 * when that is impossible exactly (zero or non-finite maximum, an inexact product). */
static int scale_exactly(const double *t, double *o, int n, double m, int target)
{
    if (!(m > 0.0) || !(m <= DBL_MAX)) return 0;  /* zero, inf or NaN */
    int e;
    (void)frexp(m, &e);  /* m in [2^(e-1), 2^e) */
    const int s = target - e;  /* in [target - 1024, target + 1074) */
    if (s > 1000) {
        /* 2^s itself may overflow: two exact steps up (no product overflows) */
        const double f1 = ldexp(1.0, 1000), f2 = ldexp(1.0, s - 1000);
        for (int i = 0; i < n; i++) o[i] = (t[i] * f1) * f2;
        return 1;
    }
    const double f = ldexp(1.0, s);
    for (int i = 0; i < n; i++) o[i] = t[i] * f;
    if (s < 0) {
        const double g = ldexp(1.0, -s);
        for (int i = 0; i < n; i++)
            if (o[i] * g != t[i]) return 0;
    }
    return 1;
}

/* Whether to try: the translations of a, on every axis, within the window (with a margin of
 * 4 below its top).  A cluster near 10^-300 or 10^300 fails this on every tuple; points of
 * moderate magnitude (the sphere's, whose exact calls are many) pass it in a few
 * instructions.  A heuristic for liveness only: the retry's soundness does not depend on when
 * it is tried, and a tuple it skips goes to the exact stages. */
static inline int worth_trying(const double *a, const double *e, double lo, double hi)
{
    for (int j = 0; j < 3; j++) {
        const double t = pred_fabs_(a[j] - e[j]);
        if (!(t >= lo && t <= 0.25 * hi)) return 1;
    }
    return 0;
}

static const double origin[3] = {0.0, 0.0, 0.0};

int pred_orient3d_filter_scaled(const double *a, const double *b, const double *c,
                                const double *d)
{
    if (!worth_trying(b, a, PRED_O3_LO, PRED_O3_HI)) return 0;
    /* the filter's own translations: the same subtractions, so the same roundings */
    const double t[9] = {b[0] - a[0], b[1] - a[1], b[2] - a[2], c[0] - a[0], c[1] - a[1],
                         c[2] - a[2], d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    double o[9], m;
    /* maximum near 2^10: the window [2^-320, 2^340] then admits a spread of 2^329 */
    if (in_window(t, 9, PRED_O3_LO, PRED_O3_HI, &m) || !scale_exactly(t, o, 9, m, 10)) return 0;
    return pred_orient3d_filter(origin, o, o + 3, o + 6, PRED_NO_STATIC);
}

int pred_insphere_filter_scaled(const double *a, const double *b, const double *c,
                                const double *d, const double *e)
{
    if (!worth_trying(a, e, PRED_IS_LO, PRED_IS_HI)) return 0;
    const double t[12] = {a[0] - e[0], a[1] - e[1], a[2] - e[2], b[0] - e[0], b[1] - e[1],
                          b[2] - e[2], c[0] - e[0], c[1] - e[1], c[2] - e[2], d[0] - e[0],
                          d[1] - e[1], d[2] - e[2]};
    double o[12], m;
    /* maximum near 2^100: the window [2^-192, 2^200] then admits a spread of 2^291 */
    if (in_window(t, 12, PRED_IS_LO, PRED_IS_HI, &m) || !scale_exactly(t, o, 12, m, 100))
        return 0;
    return pred_insphere_filter(o, o + 3, o + 6, o + 9, origin, PRED_NO_STATIC, NULL);
}
