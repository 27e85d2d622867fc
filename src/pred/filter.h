/* filter.h -- semi-static floating-point filters for orient3d and insphere (stage 1).
 *
 * Each filter returns +1 or -1 when the sign of the double evaluation is certainly the sign of
 * the exact determinant, and 0 ("undecided": go to the exact stage) otherwise.  A caller that
 * knows a box holding all its points (the kernel) also passes a static bound, the same eps
 * evaluated on the box's extents (pred_*_static_eps): it is tested first, before the maxima are
 * computed, and is sound by the same proof (proofs/filters.md section 8).  They are static
 * inline so that the kernel's cavity test can inline them; the exact stage is in orient3d.c /
 * insphere.c.
 *
 * Model (fpenv.h, checked by pred_fp_selftest): IEEE binary64, round to nearest even, every
 * + - * rounded once (no FMA contraction, no extended precision), u = 2^-53.  We use:
 *   (R1) |fl(s) - s| <= u |s| and |fl(s) - s| <= u |fl(s)| for a rounded sum or product s that
 *        does not underflow; an addition/subtraction that underflows is exact (Hauser), so the
 *        translated coordinates x~ = fl(b_x - a_x) always satisfy |x~ - x| <= u |x~|.
 *   (R2) a product that underflows has an absolute error <= eta = 2^-1075.
 *
 * ---- orient3d(a,b,c,d) = sign det[b-a; c-a; d-a] -------------------------------------------
 * Evaluation order (FIXED: proofs/ certifies exactly this expression; do not reorder):
 *     px = bx-ax  py = by-ay  pz = bz-az      (same for q = c-a, r = d-a)
 *     m1 = qy*rz - qz*ry
 *     m2 = qz*rx - qx*rz
 *     m3 = qx*ry - qy*rx
 *     det = (px*m1 + py*m2) + pz*m3
 *     X = max(|px|,|qx|,|rx|), Y = max |.y|, Z = max |.z|   (of the computed translated values)
 *     eps = ((C * X) * Y) * Z
 *     decided iff  L3 <= min(X,Y,Z)  and  max(X,Y,Z) <= H3  and  |det| > eps.
 * Error bound, term by term, as (magnitude bound | absolute error bound) pairs in the units
 * named, against the exact determinant of the exact differences (to first order in u; the
 * exact rational propagation, with all higher-order terms, is the one below):
 *     x~ (input)          | 1 X        | u X                         (R1 on the translation)
 *     q~y*r~z             | YZ(1+u)    | u YZ (rounding) + (2u+u^2) YZ (inputs) = 3u YZ
 *     m1 = diff of two    | 2YZ(1+u)^2 | 2*3u + 2u (rounding)         = 8u YZ
 *     px*m1               | 2XYZ       | 8u + 2u (input px) + 2u (rounding) = 12u XYZ
 *     px*m1 + py*m2       | 4XYZ       | 12u + 12u + 4u              = 28u XYZ
 *     det                 | 6XYZ       | 28u + 12u + 6u              = 46u XYZ
 * Exact propagation with Fractions (every (1+u) factor kept): E = 46.00000000000001 u XYZ.
 * eps is computed with 3 roundings, each >= (1-u) times its exact value (no underflow: see
 * L3), so C >= E / (1-u)^3 suffices; we add a relative slack of 2^-40 that covers (R2): an
 * underflowing product of type T (a monomial in X,Y,Z of degree k >= 2) contributes at most
 * ~eta * XYZ / T <= eta * XYZ / L3^2, and the three outer products at most eta <= 2^-115 XYZ
 * when min(X,Y,Z) >= L3; in total < 2^-112 XYZ, far below the slack 2^-40 * 46u XYZ.
 *     C3 = 5.107025913280368e-15  (= 46.00000000004 u, rounded up to a double)
 * Guards: L3 = 2^-320: then C3*X, C3*X*Y, eps >= 2^-47.5 * 2^-960 are normal, so eps is
 * computed with relative rounding only.  H3 = 2^340: every intermediate is <= 6 H3^3 (1+u)^6 <
 * 2^1023 (no overflow); an overflowing translation gives X = inf > H3 and is sent on.  A zero
 * max (all x equal, say) makes det exactly 0 but is reported as undecided (0) too.
 *
 * ---- insphere(a,b,c,d,e) ------------------------------------------------------------------
 * With a' = a-e etc. and the lifted coordinate w = |a'|^2, insphere = -det[a' aw; b' bw; c'
 * cw; d' dw] (rows (x,y,z,w)); > 0 when e is inside the sphere of positively oriented a,b,c,d.
 * Evaluation order (FIXED):
 *     ax = a_x-e_x ...  (translation by e, for a,b,c,d)
 *     ab = ax*by - bx*ay   bc = bx*cy - cx*by   cd = cx*dy - dx*cy
 *     da = dx*ay - ax*dy   ac = ax*cy - cx*ay   bd = bx*dy - dx*by
 *     abc = (az*bc - bz*ac) + cz*ab            (= det[a';b';c'] in xyz)
 *     bcd = (bz*cd - cz*bd) + dz*bc
 *     cda = (cz*da + dz*ac) + az*cd
 *     dab = (dz*ab + az*bd) + bz*da
 *     aw = (ax*ax + ay*ay) + az*az  (same for b, c, d)
 *     det = (cw*dab - dw*abc) + (aw*bcd - bw*cda)
 *     X, Y, Z = max |translated x|, |y|, |z| over a',b',c',d';  M = max(X, Y, Z)
 *     eps = ((((C * X) * Y) * Z) * M) * M
 *     decided iff  L4 <= min(X,Y,Z)  and  M <= H4  and  |det| > eps.
 * Bound form: every monomial of the determinant is x*y*z*w with |w| <= X^2+Y^2+Z^2 <= 3M^2,
 * so we count in units XYZ M^2 (a square of a coordinate counts as M^2):
 *     minors ab..          | 2XY       | 8u XY           (as m1 above)
 *     abc (3 products)     | 6XYZ      | 46u XYZ         (as det above)
 *     aw                   | 3M^2      | 3*3u + 2u + 3u  = 14u M^2
 *     cw*dab               | 18 XYZM^2 | 14u*6 + 3*46u + 18u = 240u
 *     cw*dab - dw*abc      | 36        | 480u + 36u      = 516u
 *     det                  | 72        | 516u*2 + 72u    = 1104u XYZ M^2
 * Exact propagation: E = 1104.000000000001 u; eps has 5 roundings; slack 2^-40 covers (R2):
 * with min(X,Y,Z) >= L4 every product type has degree >= 2, the worst ratio is eta / L4^5 =
 * 2^-115.
 *     C4 = 1.2256862191872893e-13  (= 1104.000000001 u, rounded up)
 * Guards: L4 = 2^-192 (eps and its partial products >= 2^-43 * 2^-960, normal);
 * H4 = 2^200: every intermediate is <= 72 M^5 (1+u)^10 < 2^1007 (no overflow).
 * These constants are ours, computed by src/pred/filter_bound.py (the propagation above in exact
 * rationals); CGAL's are 46.03u and 1122.9u for its own evaluation orders.
 */
#ifndef GTET_PRED_FILTER_H
#define GTET_PRED_FILTER_H

#include "fpenv.h"

#include <stdint.h>

/* A thread's level for the insphere filter's static test (filter_packed.h
 * pred_insphere_filter_packed_lv): a power of two w and sw, the smaller of the static bound
 * pred_insphere_static_eps(w, w, w) (PRED_NO_STATIC when w fails the guards) and the box's
 * seps, kept so that a call compares with one value; w = 0 never decides. */
typedef struct pred_is_level {
    double w, sw;
} pred_is_level;

#define PRED_O3_C 5.107025913280368e-15
#define PRED_O3_LO 0x1p-320
#define PRED_O3_HI 0x1p+340
#define PRED_IS_C 1.2256862191872893e-13
#define PRED_IS_LO 0x1p-192
#define PRED_IS_HI 0x1p+200

/* fabs clears the sign bit: one AND (x < 0 ? -x : x would keep -0.0 and cost a blend). */
static inline double pred_fabs_(double x) { return __builtin_fabs(x); }
static inline double pred_max_(double x, double y) { return x < y ? y : x; }
static inline double pred_min_(double x, double y) { return x < y ? x : y; }

/* No static bound: the filters below then use only their semi-static bound. */
#define PRED_NO_STATIC (__builtin_inf())

/* The filters again on the translations scaled by a power of two (filter_scaled.c), for a
 * tuple whose translations lie outside the window the constants are proved for (tiny or huge,
 * but of moderate spread: a cluster near 10^-300 or 10^300); 0 for any other tuple.  Sound by
 * proofs/filters.md section 11.  Called first by the exact chains (pred_orient3d_exact,
 * pred_insphere_exact), not here: a call in these inline filters keeps the compiler from
 * inlining the kernel's conflict test (+6% instructions on uniform points). */
int pred_orient3d_filter_scaled(const double *a, const double *b, const double *c,
                                const double *d);
int pred_insphere_filter_scaled(const double *a, const double *b, const double *c,
                                const double *d, const double *e);

/* Static bounds (proofs/filters.md section 8).  X, Y, Z must be upper bounds of |translated
 * coordinate| on each axis for every tuple the caller will pass, e.g. the computed extents
 * fl(max_x - min_x) of a box holding all its points (rounding is monotone, so every computed
 * difference of two of them is at most that in magnitude).  The result is the filter's eps
 * evaluated on those bounds, in the same order (the same Gappa goal 2 covers its rounding), or
 * PRED_NO_STATIC when the bounds fail the guards. */
static inline double pred_orient3d_static_eps(double X, double Y, double Z)
{
    const double lo = X < Y ? (X < Z ? X : Z) : (Y < Z ? Y : Z);
    const double hi = X < Y ? (Y < Z ? Z : Y) : (X < Z ? Z : X);
    if (!(lo >= PRED_O3_LO && hi <= PRED_O3_HI)) return PRED_NO_STATIC;
    return ((PRED_O3_C * X) * Y) * Z;
}

static inline double pred_insphere_static_eps(double X, double Y, double Z)
{
    const double lo = X < Y ? (X < Z ? X : Z) : (Y < Z ? Y : Z);
    const double M = X < Y ? (Y < Z ? Z : Y) : (X < Z ? Z : X);
    if (!(lo >= PRED_IS_LO && M <= PRED_IS_HI)) return PRED_NO_STATIC;
    return ((((PRED_IS_C * X) * Y) * Z) * M) * M;
}

/* +1 / -1 when certain, 0 undecided.  seps: a static bound (pred_orient3d_static_eps) valid
 * for this tuple, or PRED_NO_STATIC; the static test runs first because it needs no maxima. */
static inline int pred_orient3d_filter(const double *a, const double *b, const double *c,
                                       const double *d, double seps)
{
    const double px = b[0] - a[0], py = b[1] - a[1], pz = b[2] - a[2];
    const double qx = c[0] - a[0], qy = c[1] - a[1], qz = c[2] - a[2];
    const double rx = d[0] - a[0], ry = d[1] - a[1], rz = d[2] - a[2];
    const double m1 = qy * rz - qz * ry;
    const double m2 = qz * rx - qx * rz;
    const double m3 = qx * ry - qy * rx;
    const double det = (px * m1 + py * m2) + pz * m3;
    if (det > seps) return 1;   /* never taken for a NaN det or an infinite seps */
    if (det < -seps) return -1;
    if (seps == 0) return 0;    /* exact evaluation (lattice, proofs/filters.md 9): det~ = 0 */
    const double X = pred_max_(pred_max_(pred_fabs_(px), pred_fabs_(qx)), pred_fabs_(rx));
    const double Y = pred_max_(pred_max_(pred_fabs_(py), pred_fabs_(qy)), pred_fabs_(ry));
    const double Z = pred_max_(pred_max_(pred_fabs_(pz), pred_fabs_(qz)), pred_fabs_(rz));
    const double lo = pred_min_(pred_min_(X, Y), Z);
    const double hi = pred_max_(pred_max_(X, Y), Z);
    /* written so that NaN/inf (overflowed translation) fails the guard */
    if (!(lo >= PRED_O3_LO && hi <= PRED_O3_HI)) return 0;
    const double eps = ((PRED_O3_C * X) * Y) * Z;
    return (det > eps) - (det < -eps);
}

/* What pred_insphere_filter leaves in `minors` (PRED_IS_NMINORS doubles) when undecided:
 * [0..3] the computed 3x3 minors abc, bcd, cda, dab of the translated points; then, unless
 * seps == 0, [4] the computed det~ and [5] the computed ((((X*Y)*Z)*M)*M), or +inf when the
 * guard failed.  On a set of integers below 2^23 (pred_static.int23) with [5] <= PRED_IS_INT_EXACT
 * every operation of the evaluation was exact (proofs/filters.md section 12): det~ and the
 * minors are the exact values (sos.c pred_insphere_sos_rest_log). */
#define PRED_IS_NMINORS 6
#define PRED_IS_INT_EXACT 0x1p46

/* The undecided filter's record (above); returns 0 (undecided). */
static inline int pred_insphere_keep_(double *minors, double abc, double bcd, double cda,
                                      double dab, double det, double xyzmm)
{
    minors[0] = abc;
    minors[1] = bcd;
    minors[2] = cda;
    minors[3] = dab;
    minors[4] = det;
    minors[5] = xyzmm;
    return 0;
}

/* +1 / -1 when certain, 0 undecided; seps as for orient3d (pred_insphere_static_eps).  With
 * seps == 0 (a lattice: the evaluation is exact, proofs/filters.md section 9) an undecided
 * answer is an exact zero, and `minors`, when not NULL, receives the exact 3x3 minors
 * abc, bcd, cda, dab of the translated points, which the perturbation reuses (sos.c); with
 * another seps an undecided answer leaves the record described above in `minors`. */
static inline int pred_insphere_filter(const double *a, const double *b, const double *c,
                                       const double *d, const double *e, double seps,
                                       double *minors)
{
    const double ax = a[0] - e[0], ay = a[1] - e[1], az = a[2] - e[2];
    const double bx = b[0] - e[0], by = b[1] - e[1], bz = b[2] - e[2];
    const double cx = c[0] - e[0], cy = c[1] - e[1], cz = c[2] - e[2];
    const double dx = d[0] - e[0], dy = d[1] - e[1], dz = d[2] - e[2];
    const double ab = ax * by - bx * ay;
    const double bc = bx * cy - cx * by;
    const double cd = cx * dy - dx * cy;
    const double da = dx * ay - ax * dy;
    const double ac = ax * cy - cx * ay;
    const double bd = bx * dy - dx * by;
    const double abc = (az * bc - bz * ac) + cz * ab;
    const double bcd = (bz * cd - cz * bd) + dz * bc;
    const double cda = (cz * da + dz * ac) + az * cd;
    const double dab = (dz * ab + az * bd) + bz * da;
    const double aw = (ax * ax + ay * ay) + az * az;
    const double bw = (bx * bx + by * by) + bz * bz;
    const double cw = (cx * cx + cy * cy) + cz * cz;
    const double dw = (dx * dx + dy * dy) + dz * dz;
    const double det = (cw * dab - dw * abc) + (aw * bcd - bw * cda);
    if (det > seps) return 1;
    if (det < -seps) return -1;
    if (seps == 0) {
        if (minors) {
            minors[0] = abc;
            minors[1] = bcd;
            minors[2] = cda;
            minors[3] = dab;
        }
        return 0;
    }
    const double X = pred_max_(pred_max_(pred_fabs_(ax), pred_fabs_(bx)),
                               pred_max_(pred_fabs_(cx), pred_fabs_(dx)));
    const double Y = pred_max_(pred_max_(pred_fabs_(ay), pred_fabs_(by)),
                               pred_max_(pred_fabs_(cy), pred_fabs_(dy)));
    const double Z = pred_max_(pred_max_(pred_fabs_(az), pred_fabs_(bz)),
                               pred_max_(pred_fabs_(cz), pred_fabs_(dz)));
    const double lo = pred_min_(pred_min_(X, Y), Z);
    const double M = pred_max_(pred_max_(X, Y), Z);
    if (!(lo >= PRED_IS_LO && M <= PRED_IS_HI))
        return minors ? pred_insphere_keep_(minors, abc, bcd, cda, dab, det, __builtin_inf()) : 0;
    const double eps = ((((PRED_IS_C * X) * Y) * Z) * M) * M;
    if (minors && !(det > eps) && !(det < -eps))
        pred_insphere_keep_(minors, abc, bcd, cda, dab, det, (((X * Y) * Z) * M) * M);
    return (det > eps) - (det < -eps);
}

/* the kernel's packed (SSE2, AVX2) evaluations of pred_insphere_filter */
#include "filter_packed.h"

#endif
