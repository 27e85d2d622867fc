/* orient3d.c -- orient3d as one chain: filter (filter.h) -> small integers -> 60-bit integer
 * form (exact_int.c) -> expansions -> GMP, each exact stage returning the exact sign when its domain applies (pred_internal.h).
 * Correctness: the filter's sign is certain when it decides (filter.h); each exact stage is
 * exact on its domain and GMP on all finite doubles, so the result is the exact sign. */
#include "filter.h"
#include "pred_internal.h"

int pred_orient3d_exact(const double *a, const double *b, const double *c, const double *d,
                        pred_counters *cnt)
{
    int s;
    cnt->orient_exact++;
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
