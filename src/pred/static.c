/* static.c -- what the predicates may assume about a whole point set (pred_static).
 *
 * A caller that passes only points of one known set (the kernel: the vertices) gets two things
 * from pred_static_init, each proved in proofs/filters.md:
 *  - static bounds (section 8): the filters' eps evaluated on the set's computed extents
 *    fl(max - min); a filter answers as soon as |det~| exceeds it, before computing maxima;
 *  - lattice exactness (section 9): when every coordinate is an integer multiple of one power
 *    of two 2^s and the extents are at most E units of 2^s, every operation of a filter's
 *    evaluation is exact (all intermediates are integer multiples of 2^(k s), k <= 5, below
 *    2^53 units, inside the exponent range), so det~ IS the determinant: the static bound is 0
 *    and a zero is an exact zero, with no exact stage.  orient3d: |intermediates| <= 6 E^3,
 *    E <= PRED_O3_LATTICE_E; insphere: <= 72 E^5, E <= PRED_IS_LATTICE_E.  This is what makes
 *    integer grids and lattices (every insphere of a cube is 0) cheap.
 * The perturbation (sos.c) then runs from the known zero.
 */
#include "pred_internal.h"

#include <math.h>
#include <string.h>

const pred_static pred_static_none = {PRED_NO_STATIC, PRED_NO_STATIC, 0, 0, 0};

/* The exponent of the lowest set bit of x != 0 (x = odd * 2^q). */
static int low_exponent(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    const int ef = (int)((u >> 52) & 0x7ff);
    uint64_t m = u & ((UINT64_C(1) << 52) - 1);
    if (ef == 0) return -1074 + __builtin_ctzll(m);  /* subnormal: m != 0 */
    m |= UINT64_C(1) << 52;
    return ef - 1075 + __builtin_ctzll(m);
}

void pred_static_init(const double *xyz, size_t stride, size_t n, pred_static *ps)
{
    pred_static_init_mt(xyz, stride, n, 1, ps, NULL);
}

void pred_static_init_mt(const double *xyz, size_t stride, size_t n, int threads,
                         pred_static *ps, double box[6])
{
    *ps = pred_static_none;
    if (box) memset(box, 0, 6 * sizeof *box);
    if (n == 0) return;
    double lo0 = xyz[0], lo1 = xyz[1], lo2 = xyz[2], hi0 = xyz[0], hi1 = xyz[1], hi2 = xyz[2];
    int s = 2000;  /* the lattice exponent: min over nonzero coordinates */
    /* NaN never reaches here (validate rejects it); min/max are exact, order-free reductions */
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && n > 65536) \
    reduction(min : lo0, lo1, lo2, s) reduction(max : hi0, hi1, hi2)
    for (size_t i = 0; i < n; i++) {
        const double *q = xyz + stride * i;
        lo0 = q[0] < lo0 ? q[0] : lo0;
        lo1 = q[1] < lo1 ? q[1] : lo1;
        lo2 = q[2] < lo2 ? q[2] : lo2;
        hi0 = q[0] > hi0 ? q[0] : hi0;
        hi1 = q[1] > hi1 ? q[1] : hi1;
        hi2 = q[2] > hi2 ? q[2] : hi2;
        for (int d = 0; d < 3; d++)
            if (q[d] != 0) {
                const int e = low_exponent(q[d]);
                s = e < s ? e : s;
            }
    }
    const double lo[3] = {lo0, lo1, lo2}, hi[3] = {hi0, hi1, hi2};
    if (box) box[0] = lo0, box[1] = lo1, box[2] = lo2, box[3] = hi0, box[4] = hi1, box[5] = hi2;
    /* integers (lowest set bit at 2^0 or above, or all zero) of magnitude < 2^23: the domain
     * of pred_insphere_int for every tuple of the set (NOTES.md E30) */
    const double lim = 0x1p23;
    ps->int23 = s >= 0 && lo0 > -lim && lo1 > -lim && lo2 > -lim && hi0 < lim && hi1 < lim &&
                hi2 < lim;
    const double X = hi[0] - lo[0], Y = hi[1] - lo[1], Z = hi[2] - lo[2];
    if (!(X <= PRED_O3_HI && Y <= PRED_O3_HI && Z <= PRED_O3_HI)) return;  /* inf, NaN, huge */
    ps->o3_seps = pred_orient3d_static_eps(X, Y, Z);
    ps->is_seps = pred_insphere_static_eps(X, Y, Z);
    if (s == 2000) s = 0;  /* every coordinate is 0 */
    /* extents in units of 2^s; a difference of two multiples of 2^s below 2^53 units is exact,
     * so a computed extent this small is the exact one */
    const double M = X > Y ? (X > Z ? X : Z) : (Y > Z ? Y : Z);
    const double units = s >= -1074 && s <= 1023 ? M / ldexp(1.0, s) : 1e300;
    if (units <= PRED_O3_LATTICE_E && 3 * s >= -1074 && 3 * s + 53 <= 1023) {
        ps->o3_exact = 1;
        ps->o3_seps = 0;
    }
    if (units <= PRED_IS_LATTICE_E && 5 * s >= -1074 && 5 * s + 53 <= 1023) {
        ps->is_exact = 1;
        ps->is_seps = 0;
    }
}

int pred_orient3d_st(const double *a, const double *b, const double *c, const double *d,
                     const pred_static *ps, pred_counters *cnt)
{
    cnt->orient_calls++;
    const int s = pred_orient3d_filter(a, b, c, d, ps->o3_seps);
    if (s != 0) return s;
    return pred_orient3d_rest(a, b, c, d, ps, cnt);
}

int pred_orient3d_rest(const double *a, const double *b, const double *c, const double *d,
                       const pred_static *ps, pred_counters *cnt)
{
    if (ps->o3_exact) {  /* det~ == 0 is the exact determinant */
        cnt->orient_zero++;
        return 0;
    }
    return pred_orient3d_exact(a, b, c, d, cnt);
}
