/* counters.c -- the public predicate wrappers of gigatet.h and their per-thread counters.
 * The record is _Thread_local (the one piece of static mutable state the library allows):
 * each thread sees and resets only its own counts, so the wrappers stay reentrant. */
#include "../pred/pred.h"

#include <string.h>

static _Thread_local gtet_pred_counters tl_counters;

int gtet_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    return pred_orient3d(a, b, c, d, &tl_counters);
}

int gtet_insphere(const double a[3], const double b[3], const double c[3], const double d[3],
                  const double e[3])
{
    return pred_insphere(a, b, c, d, e, &tl_counters);
}

int gtet_insphere_sos(const double a[3], const double b[3], const double c[3],
                      const double d[3], const double e[3])
{
    return pred_insphere_sos(a, b, c, d, e, &tl_counters);
}

int gtet_ghost_conflict(const double a[3], const double b[3], const double c[3],
                        const double e[3])
{
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
