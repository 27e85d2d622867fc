/* slabs.h -- the retries' partition of a parallel pass into slabs between planes across one
 * axis (prefix kpar_); see slabs.c.  Used by parallel.c for a round's passes after its first
 * (NOTES.md E40) and exposed for the tests of obligation O1 (proofs/parallel.md): every point
 * of slice k has colour k. */
#ifndef GTET_SLABS_H
#define GTET_SLABS_H

#include <stddef.h>
#include <stdint.h>

/* A pass's slabs: slab k holds the coordinates x along `axis` with cut[k] <= x < cut[k + 1]
 * (cut[0] = -infinity, cut[nth] = +infinity, implied). */
typedef struct kpar_slab_cuts {
    int axis;
    int nth;
    double cut[256];
} kpar_slab_cuts;

/* The slab of coordinate x: the number of cuts cut[1..nth) at or below x. */
static inline int kpar_slab_of(double x, const kpar_slab_cuts *s)
{
    int c = 0;
    while (c + 1 < s->nth && x >= s->cut[c + 1]) c++;
    return c;
}

/* Cut the pending points pts[0..np) (vertex ids into v, 3 doubles each) into nth slabs of
 * about equal counts across the axis on which their middle halves spread widest (the largest
 * distance between the 1/4 and 3/4 quantiles of the coordinates of pts[0], pts[s], pts[2 s],
 * ... with s = np / 4096 + 1; the lowest axis on ties), and reorder pts so
 * that slice k = pts[begin[k] .. end[k]) holds the points of slab k in their previous order.
 * scratch: np doubles; tmp: np entries.  Returns 0, with nothing changed, when some slab
 * would hold fewer than np / (2 nth) points (equal coordinates, a flat set), or nth < 2. */
int kpar_slabs(const double *v, uint32_t *pts, size_t np, int nth, double *scratch,
               uint32_t *tmp, size_t begin[], size_t end[], kpar_slab_cuts *out);

/* The element of rank r (0-based) of a[0..n) in ascending order, r < n; a is reordered
 * (a[0..r) <= a[r] <= a[r+1..n) on return).  No NaN.  Exposed for the tests. */
double kpar_select(double *a, size_t n, size_t r);

#endif
