/* orient3d.c -- orient3d as one chain: filter (filter.h) -> small integers -> 60-bit integer
 * form (exact_int.c) -> expansions -> GMP, each exact stage returning the exact sign when its domain applies (pred_internal.h).
 * Correctness: the filter's sign is certain when it decides (filter.h); each exact stage is
 * exact on its domain and GMP on all finite doubles, so the result is the exact sign. */
#include "filter.h"
#include "pred_internal.h"

int pred_orient3d_exact(const double *a, const double *b, const double *c, const double *d,
                        pred_counters *cnt)
{
    /* a cluster far from 1 (translations outside the filter's window): the filter on the
     * translations scaled by 2^s first (filter_scaled.c); not an exact call */
    int s = pred_orient3d_filter_scaled(a, b, c, d);
    if (s != 0) return s;
    cnt->orient_exact++;
    /* four points on one axis-aligned plane (a coordinate equal in all four): a column of
     * the translated matrix is exactly zero, so is the determinant (plane + apex inputs,
     * boxes, the faces of grids) */
    for (int j = 0; j < 3; j++)
        if (a[j] == b[j] && a[j] == c[j] && a[j] == d[j]) {
            cnt->orient_zero++;
            return 0;
        }
    /* three of them on an axis-aligned plane x_j = P, the fourth (m) off it: the sign is
     * -(-1)^(m+j) sign(m_j - P) orient2d of the other three (in order) in the other two axes
     * (orient3d is the sign of det[b-a; c-a; d-a] = -det[p 1]; subtract P times the ones
     * column from column j and expand along it).  A subnormal apex over a plane made every
     * such test a GMP call (its bits span too many binades for the integer forms). */
    {
        const double *p[4] = {a, b, c, d};
        for (int j = 0; j < 3; j++) {
            const double P = a[j] == b[j] || a[j] == c[j] ? a[j] : b[j];
            int off = -1, n_off = 0;
            for (int k = 0; k < 4; k++)
                if (p[k][j] != P) {
                    off = k;
                    n_off++;
                }
            if (n_off != 1) continue;
            const int u = j == 0 ? 1 : 0, w = j == 2 ? 1 : 2;
            const double *r[3];
            for (int k = 0, i = 0; k < 4; k++)
                if (k != off) r[i++] = p[k];
            const int h = p[off][j] > P ? 1 : -1;
            const int parity = (off + j) & 1 ? 1 : -1;  /* -(-1)^(m+j) */
            s = parity * h * pred_orient2d_exact(r[0], r[1], r[2], u, w);
            cnt->orient_int++;
            if (s == 0) cnt->orient_zero++;
            return s;
        }
    }
    if (pred_orient3d_int(a, b, c, d, &s) || pred_orient3d_wide(a, b, c, d, &s)) {
        cnt->orient_int++;
    } else if (!pred_orient3d_exp(a, b, c, d, &s)) {
        cnt->orient_gmp++;
        s = pred_orient3d_gmp(a, b, c, d);
    }
    if (s == 0) cnt->orient_zero++;
    return s;
}

int pred_orient3d(const double *a, const double *b, const double *c, const double *d,
                  pred_counters *cnt)
{
    cnt->orient_calls++;
    int s = pred_orient3d_filter(a, b, c, d, PRED_NO_STATIC);
    if (s != 0) return s;
    return pred_orient3d_exact(a, b, c, d, cnt);
}
