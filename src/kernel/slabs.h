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

/* Where the curve re-enters a slab (NOTES.md E100).  A slab pass keeps each slab's points in
 * their previous order (a Moore order, kpar_slab_split), and that order leaves a slab and comes
 * back: consecutive points of a slice can be far apart, with the other slab's tets between
 * them.  A walk from the previous point's tet then meets a tet of another thread and defers
 * the point, and every next one until the slice's next checkpoint (parallel.c).  A run of
 * slab k is a maximal sequence of consecutive points (in pts' order) of slab k; its start is
 * the offset, within slice k, of its first point; its gap is the number of points of other
 * slabs just before it.  at[k * cap + j] (j < n[k]): the starts of slab k's runs whose gap is
 * at least min_gap[k], increasing; min_gap[k] is the least power of two that leaves at most cap
 * of them (the run that starts slice k, gap 0 or not, is never listed: the pass's start tet
 * covers it). */
typedef struct kpar_runs {
    uint32_t *at;         /* nth * cap entries */
    size_t cap;
    size_t n[256];
    size_t min_gap[256];
} kpar_runs;

/* Cut the pending points pts[0..np) (vertex ids into v, 3 doubles each) into nth slabs of
 * about equal counts across the axis whose cuts fall where the points are sparsest: on the
 * sample pts[0], pts[s], pts[2 s], ... (s = np / 4096 + 1, n points), the least sum over the
 * cuts k of 1 / (the distance between the sample's quantiles of ranks n k / nth -+ n / 64);
 * the lowest axis on ties; the widest 1/4 .. 3/4 quantile spread when every axis has a
 * window of width 0.  Then reorder pts so
 * that slice k = pts[begin[k] .. end[k]) holds the points of slab k in their previous order.
 * scratch: np doubles; tmp: np entries.  Returns 0, with nothing changed, when some slab
 * would hold fewer than np / (2 nth) points (equal coordinates, a flat set), or nth < 2. */
int kpar_slabs(const double *v, uint32_t *pts, size_t np, int nth, double *scratch,
               uint32_t *tmp, size_t begin[], size_t end[], kpar_slab_cuts *out);

/* The cuts of kpar_slabs on `axis` (0..2), or on kpar_slabs' axis (-1), without reordering
 * anything: 0 when some slab would hold fewer than np / (2 nth) points (or nth < 2).
 * scratch: np doubles. */
int kpar_slab_cuts_on(const double *v, const uint32_t *pts, size_t np, int nth, int axis,
                      double *scratch, kpar_slab_cuts *out);

/* Reorder pts[0..np) so that slice k = pts[begin[k] .. end[k]) holds the points of slab k of s
 * in their previous order.  tmp: np entries.  runs: NULL, or its at, cap given, the run starts
 * of the previous order are filled in (kpar_runs above; deterministic: from the coordinates
 * and the order alone). */
void kpar_slab_split(const double *v, uint32_t *pts, size_t np, const kpar_slab_cuts *s,
                     uint32_t *tmp, size_t begin[], size_t end[], kpar_runs *runs);

/* kpar_slab_split with given cuts s (e.g. from a sample of the points), when every slab then
 * holds at least np / (2 s->nth) points; else 0, with nothing changed (runs too). */
int kpar_slabs_at(const double *v, uint32_t *pts, size_t np, const kpar_slab_cuts *s,
                  uint32_t *tmp, size_t begin[], size_t end[], kpar_runs *runs);

/* Of every stride-th tet slot t < nt of tv (4 vertex ids a slot, kmesh.h: a dead slot, with
 * KM_DEAD in its first id, and a ghost, KM_GHOST 4th, are skipped), the tets whose four vertices
 * do not all have one colour: cross[0] under the colours col[] (a round's Moore slices),
 * cross[1 + d] under the slabs s[d] (d = 0, 1, 2; s[d].axis is d).  Those are the tets where a
 * pass's cavities meet another thread's; long ones (the concavities of a scan, the inside of a
 * flat shell) cross a folded Moore boundary or a plane along the thin axis far more often
 * than the right plane (NOTES.md E70).  nth threads count. */
void kpar_crossing(const uint32_t *tv, size_t nt, size_t stride, const double *v,
                   const uint8_t *col, const kpar_slab_cuts s[3], int nth, size_t cross[4]);

/* The first pass's partition from kpar_crossing's counts: the axis d (lowest on ties) of the
 * fewest crossing tets when cross[1 + d] < SLAB_FIRST_NUM / SLAB_FIRST_DEN of cross[0] (a
 * clear gain: on uniform points, spheres and clusters the Moore slices cross as few or fewer,
 * and E12 / E21 balance their cost), else -1 (keep the Moore slices). */
#define SLAB_FIRST_NUM 3
#define SLAB_FIRST_DEN 4
int kpar_first_axis(const size_t cross[4]);

/* The element of rank r (0-based) of a[0..n) in ascending order, r < n; a is reordered
 * (a[0..r) <= a[r] <= a[r+1..n) on return).  No NaN.  Exposed for the tests. */
double kpar_select(double *a, size_t n, size_t r);

#endif
