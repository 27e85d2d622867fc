/* insphere.c -- insphere as one chain: filter (filter.h) -> small integers -> 60-bit integer
 * form (fixed-width, exact_int.c) -> expansions -> GMP (pred_internal.h); same argument as
 * orient3d.c.  The integer form decides near-co-spherical non-integer tuples (points rounded
 * onto a sphere: the filter decides none of them) without GMP's allocations. */
#include "filter.h"
#include "pred_internal.h"

int pred_insphere_exact(const double *a, const double *b, const double *c, const double *d,
                        const double *e, pred_counters *cnt)
{
    int s;
    cnt->insphere_exact++;
    if (pred_insphere_int(a, b, c, d, e, &s) || pred_insphere_wide(a, b, c, d, e, &s)) {
        cnt->insphere_int++;
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
