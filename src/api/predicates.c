/* predicates.c -- the public predicate wrappers of gigatet.h and their per-thread counters.
 * The record is _Thread_local (the one piece of static mutable state the library allows):
 * each thread sees and resets only its own counts, so the wrappers stay reentrant. */
#include "../pred/pred.h"

#include <string.h>

static _Thread_local gtet_pred_counters tl_counters;

/* 1 when the n points' coordinates are all finite.  x - x is +0 for a finite x and NaN for NaN
 * and both infinities (IEEE 754, every rounding mode), and a sum with a NaN term is NaN: one
 * compare for the tuple.  The public predicates answer 0 (no sign) on a NaN or infinite
 * coordinate instead of passing it to the exact stages, where GMP's mpz_set_d would raise
 * SIGFPE and kill the caller (NOTES.md E160); the kernel calls pred_* on validated points. */
static int finite_points(const double *const p[], int n)
{
    double z = 0.0;
    for (int i = 0; i < n; i++) z += (p[i][0] - p[i][0]) + (p[i][1] - p[i][1]) + (p[i][2] - p[i][2]);
    return z == 0.0;
}

int gtet_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    if (!finite_points((const double *const[]){a, b, c, d}, 4)) return 0;
    return pred_orient3d(a, b, c, d, &tl_counters);
}

int gtet_insphere(const double a[3], const double b[3], const double c[3], const double d[3],
                  const double e[3])
{
    if (!finite_points((const double *const[]){a, b, c, d, e}, 5)) return 0;
    return pred_insphere(a, b, c, d, e, &tl_counters);
}

int gtet_insphere_sos(const double a[3], const double b[3], const double c[3],
                      const double d[3], const double e[3])
{
    if (!finite_points((const double *const[]){a, b, c, d, e}, 5)) return 0;
    return pred_insphere_sos(a, b, c, d, e, &tl_counters);
}

int gtet_ghost_conflict(const double a[3], const double b[3], const double c[3],
                        const double e[3])
{
    if (!finite_points((const double *const[]){a, b, c, e}, 4)) return 0;
    return pred_ghost_conflict(a, b, c, e, &tl_counters);
}

void gtet_pred_counters_get(gtet_pred_counters *out)
{
    if (out) *out = tl_counters;
}

void gtet_pred_counters_reset(void)
{
    memset(&tl_counters, 0, sizeof tl_counters);
}
