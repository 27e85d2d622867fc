/* insphere.c -- insphere as one chain: filter (filter.h) -> small integers -> 60-bit integer
 * form -> 122-bit integer form (exact_int.c) -> expansions -> GMP (pred_internal.h); same
 * argument as orient3d.c.  The integer forms decide near-co-spherical non-integer tuples
 * (points rounded onto a sphere: the filter decides none of them) without GMP's allocations;
 * the 122-bit form takes the ~3% of them that span more than 60 binades (a coordinate near
 * 0, whose ulp is far below the others'). */
#include "filter.h"
#include "pred_internal.h"

/* e and three of a,b,c,d on one axis-aligned plane x_j = const, the fourth (m) off it.  The
 * predicate's sign is that of -det M, M the 4x4 matrix of the rows p - e (columns x, y, z,
 * |p - e|^2): the filter's (cw dab - dw abc) + (aw bcd - bw cda) is its expansion along the
 * lift column with the opposite sign.  Column j of M has one non-zero entry, h = m_j - e_j in
 * row m, so
 *     -det M = -(-1)^(m+j) h det3,
 * det3 being the rows p - e of the other three (in order), columns u < w (the other two axes)
 * and the lift: pred_lifted2d_exact.  Its bits span only the plane's coordinates, so the wide
 * integer form takes it where the whole tuple spans too many binades for it (a plane and a
 * subnormal apex went to GMP for every insphere).  Returns 0 when the case does not apply. */
static int insphere_axis_plane(const double *const *p, const double *e, int *sign)
{
    for (int j = 0; j < 3; j++) {
        int off = -1, n_off = 0;
        for (int k = 0; k < 4; k++)
            if (p[k][j] != e[j]) {
                off = k;
                n_off++;
            }
        if (n_off != 1) continue;
        const int u = j == 0 ? 1 : 0, w = j == 2 ? 1 : 2;
        const double *r[3];
        for (int k = 0, i = 0; k < 4; k++)
            if (k != off) r[i++] = p[k];
        const int h = p[off][j] > e[j] ? 1 : -1;
        const int parity = (off + j) & 1 ? 1 : -1;  /* -(-1)^(m+j) */
        *sign = parity * h * pred_lifted2d_exact(r[0], r[1], r[2], e, u, w);
        return 1;
    }
    return 0;
}

int pred_insphere_exact(const double *a, const double *b, const double *c, const double *d,
                        const double *e, pred_counters *cnt)
{
    /* small integers first (grids, the paraboloid: NOTES.md E30): the scaled filter never
     * decides such a tuple (its translations are integers below 2^24, so every per-axis
     * maximum is 0 or inside the filter's window, where the retry returns 0), so the answer
     * and the counters are those of the chain below, without its ~90 instructions */
    int s;
    if (pred_insphere_int(a, b, c, d, e, &s)) {
        cnt->insphere_exact++;
        cnt->insphere_int++;
        if (s == 0) cnt->insphere_zero++;
        return s;
    }
    /* a cluster far from 1 (translations outside the filter's window): the filter on the
     * translations scaled by 2^s first (filter_scaled.c); not an exact call */
    s = pred_insphere_filter_scaled(a, b, c, d, e);
    if (s != 0) return s;
    cnt->insphere_exact++;
    const double *p[4] = {a, b, c, d};
    if (insphere_axis_plane(p, e, &s)) {
        cnt->insphere_int++;
    } else if (pred_insphere_wide(a, b, c, d, e, &s)) {
        cnt->insphere_int++;
    } else if (pred_insphere_wide122(a, b, c, d, e, &s)) {
        cnt->insphere_int++;
        cnt->insphere_int122++;
    } else if (!pred_insphere_exp(a, b, c, d, e, &s)) {
        cnt->insphere_gmp++;
        s = pred_insphere_gmp(a, b, c, d, e);
    }
    if (s == 0) cnt->insphere_zero++;
    return s;
}

int pred_insphere(const double *a, const double *b, const double *c, const double *d,
                  const double *e, pred_counters *cnt)
{
    cnt->insphere_calls++;
    int s = pred_insphere_filter(a, b, c, d, e, PRED_NO_STATIC, NULL);
    if (s != 0) return s;
    return pred_insphere_exact(a, b, c, d, e, cnt);
}
