/* slabs.c -- the partition of a round's retry passes (parallel.c) into slabs between planes
 * across one axis, at quantiles of the pending points (NOTES.md E40).
 *
 * Why planes: after a round's first pass (Moore-curve slices, slices.c) the deferred points
 * are those whose cavities met a tet with vertices of two colours.  On surface samples of
 * scanned meshes the tets spanning the surface's concavities are long (1/16-1/4 of the box
 * diagonal: NOTES.md E21 / colour2) and cross the first pass's colour boundary -- a union of
 * Moore cells with a large, folded area -- everywhere, so the deferred points spread over the
 * whole slice and a retry with other Moore cuts inserted none of them (the round then went
 * serial: 114k of 833k points on the Bunny).  A median plane has the least boundary a cut at
 * equal counts can have on a compact set: a retry on it inserts 70-85% of them in parallel.
 *
 * Which axis: the deferred points crowd along the last pass's colour boundary, and a median
 * plane that runs along part of that boundary re-defers the crowd (a dense cluster cut at a
 * Moore cell's face x = 1/2 + 2^-11 in its first pass: its deferred points' x-median lay on
 * that face and the retry re-deferred 25% of them).  The points a plane re-defers are those
 * within about a cavity's reach of it, as many as the pending points' density across the
 * axis at the cut; so each cut's axis is scored by the width of the quantile window around it
 * (1/32 of a sample of the pending points, centred on the cut's rank), and the axis whose cuts
 * have the widest windows (the least sum of 1/width) wins (NOTES.md E178).  Widest windows,
 * not widest spread: a spread counts where the points are, not where the cut falls.
 *
 * Obligation O1 (proofs/parallel.md): the cuts and every vertex's colour are computed before the
 * region from the coordinates alone (kpar_slab_of), and slice k is exactly the pending points of
 * slab k.  Deterministic: the quantiles are the same whatever the thread count or run.
 */
#include "slabs.h"

#include "kmesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void swap_d(double *a, size_t i, size_t j)
{
    const double t = a[i];
    a[i] = a[j];
    a[j] = t;
}

static int cmp_double(const void *p, const void *q)
{
    const double x = *(const double *)p, y = *(const double *)q;
    return (x > y) - (x < y);
}

/* Quickselect with a median-of-three pivot and Hoare's partition; after 2 * 64 rounds
 * (an adversarial order) the rest of the range is sorted instead, so the worst case is
 * O(n log n). */
double kpar_select(double *a, size_t n, size_t r)
{
    size_t lo = 0, hi = n - 1;
    for (int budget = 128; hi > lo; budget--) {
        if (budget == 0) {
            qsort(a + lo, hi - lo + 1, sizeof *a, cmp_double);
            return a[r];
        }
        const size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < a[lo]) swap_d(a, mid, lo);
        if (a[hi] < a[lo]) swap_d(a, hi, lo);
        if (a[hi] < a[mid]) swap_d(a, hi, mid);
        const double p = a[mid];  /* a[lo] <= p <= a[hi]: both scans stop inside the range */
        size_t i = lo, j = hi;
        for (;;) {
            while (a[i] < p) i++;
            while (a[j] > p) j--;
            if (i >= j) break;
            swap_d(a, i, j);
            i++;
            j--;
        }
        /* now a[lo..j] <= p <= a[j+1..hi] (j < hi: both parts are non-empty) */
        if (i == j) {  /* a[i] == p, the parts are a[lo..i-1] and a[i+1..hi] */
            if (r == i) return p;
            if (r < i) hi = i - 1;
            else lo = i + 1;
        } else if (r <= j) {
            hi = j;
        } else {
            lo = j + 1;
        }
    }
    return a[r];
}

/* The distance between the 1/4 and 3/4 quantiles of the sorted sample a[0..n). */
static double middle_spread(const double *a, size_t n)
{
    return a[3 * n / 4] - a[n / 4];
}

/* The crowd at the cuts of nth slabs across `axis`: the sum over the cuts k = 1..nth-1 of
 * 1 / (the width of the window of sample ranks r_k - n/64 .. r_k + n/64 around the cut's rank
 * r_k = n k / nth), on a sample of every stride-th point (an estimate is all the choice of
 * the axis needs), sorted into a[0..*n_out); INFINITY when a window has width 0 (equal
 * coordinates at a cut). */
#define SPREAD_SAMPLE 4096
#define CROWD_WINDOW 64  /* half a window: 1/64 of the sample on each side of the cut */
static double cut_crowd(const double *v, const uint32_t *pts, size_t np, int nth, int axis,
                        double *a, size_t *n_out)
{
    const size_t stride = np / SPREAD_SAMPLE + 1;
    size_t n = 0;
    for (size_t i = 0; i < np; i += stride) a[n++] = v[3 * (size_t)pts[i] + axis];
    qsort(a, n, sizeof *a, cmp_double);
    *n_out = n;
    const size_t w = n / CROWD_WINDOW ? n / CROWD_WINDOW : 1;
    double sum = 0.0;
    for (int k = 1; k < nth; k++) {
        const size_t r = n * (size_t)k / (size_t)nth;
        const size_t lo = r >= w ? r - w : 0, hi = r + w < n ? r + w : n - 1;
        const double width = a[hi] - a[lo];
        if (!(width > 0)) return INFINITY;
        sum += 1.0 / width;
    }
    return sum;
}

/* The axis of a retry's slabs: the least crowd at the cuts (cut_crowd), the lowest axis on
 * ties; when every axis has equal coordinates at some cut, the widest middle spread. */
static int slab_axis(const double *v, const uint32_t *pts, size_t np, int nth, double *a)
{
    int axis = 0, wide = 0;
    double least = INFINITY, widest = -1.0;
    for (int d = 0; d < 3; d++) {
        size_t n;
        const double crowd = cut_crowd(v, pts, np, nth, d, a, &n);
        const double spread = middle_spread(a, n);
        if (crowd < least) least = crowd, axis = d;
        if (spread > widest) widest = spread, wide = d;
    }
    return least < INFINITY ? axis : wide;
}

/* Every slab of s holds at least np / (2 nth) of the points. */
static int balanced(const double *v, const uint32_t *pts, size_t np, const kpar_slab_cuts *s)
{
    size_t cnt[256] = {0};
    for (size_t i = 0; i < np; i++) cnt[kpar_slab_of(v[3 * (size_t)pts[i] + s->axis], s)]++;
    for (int k = 0; k < s->nth; k++)
        if (cnt[k] < np / (2 * (size_t)s->nth)) return 0;
    return 1;
}

int kpar_slab_cuts_on(const double *v, const uint32_t *pts, size_t np, int nth, int axis,
                      double *scratch, kpar_slab_cuts *out)
{
    if (nth < 2 || nth > 256 || np < 4 * (size_t)nth || axis < -1 || axis > 2) return 0;
    if (axis < 0) axis = slab_axis(v, pts, np, nth, scratch);
    kpar_slab_cuts s = {.axis = axis, .nth = nth};
    for (size_t i = 0; i < np; i++) scratch[i] = v[3 * (size_t)pts[i] + axis];
    size_t done = 0;  /* scratch[0..done) lies below every later rank */
    for (int k = 1; k < nth; k++) {
        const size_t r = np * (size_t)k / (size_t)nth;
        s.cut[k] = kpar_select(scratch + done, np - done, r - done);
        done = r;
    }
    if (!balanced(v, pts, np, &s)) return 0;
    *out = s;
    return 1;
}

int kpar_slabs_at(const double *v, uint32_t *pts, size_t np, const kpar_slab_cuts *s,
                  uint32_t *tmp, size_t begin[], size_t end[], kpar_runs *runs)
{
    if (s->nth < 2 || s->nth > 256 || s->axis < 0 || s->axis > 2 || !balanced(v, pts, np, s))
        return 0;
    kpar_slab_split(v, pts, np, s, tmp, begin, end, runs);
    return 1;
}

/* floor(log2(g)), g >= 1. */
static int gap_bin(size_t g)
{
    return 63 - __builtin_clzll((unsigned long long)g);
}

/* min_gap[k] of the runs (slabs.h) from the histogram of slab k's gaps by floor(log2(gap)):
 * the least power of two that leaves at most cap runs; 2^32 (none) when even the longest
 * gaps are too many. */
static void runs_min_gap(const uint32_t hist[][32], int nth, kpar_runs *r)
{
    for (int k = 0; k < nth; k++) {
        size_t above = 0;
        int b = 32;
        while (b > 0 && above + hist[k][b - 1] <= r->cap) above += hist[k][--b];
        r->min_gap[k] = (size_t)1 << b;
        r->n[k] = 0;
    }
}

/* Two sweeps over the points: the counts per slab (and with runs, the histogram of the gaps:
 * a point's gap is the number of points between it and its slab's previous one, 0 inside a
 * run; a slab's first point has none), then the scatter (and the run starts written). */
void kpar_slab_split(const double *v, uint32_t *pts, size_t np, const kpar_slab_cuts *s,
                     uint32_t *tmp, size_t begin[], size_t end[], kpar_runs *runs)
{
    size_t cnt[256] = {0}, last[256];
    uint32_t hist[256][32];  /* per slab, runs by floor(log2(gap)); gaps < np < 2^32 */
    const int nth = s->nth;
    for (int k = 0; k < nth; k++) last[k] = SIZE_MAX;
    if (runs) memset(hist, 0, (size_t)nth * sizeof hist[0]);
    for (size_t i = 0; i < np; i++) {
        const int k = kpar_slab_of(v[3 * (size_t)pts[i] + s->axis], s);
        cnt[k]++;
        if (runs && last[k] != SIZE_MAX && i - last[k] > 1) hist[k][gap_bin(i - last[k] - 1)]++;
        last[k] = i;
    }
    if (runs) runs_min_gap((const uint32_t(*)[32])hist, nth, runs);
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        begin[k] = at;
        at += cnt[k];
        end[k] = begin[k];  /* the fill position; ends at begin[k] + cnt[k] */
        last[k] = SIZE_MAX;
    }
    for (size_t i = 0; i < np; i++) {
        const int k = kpar_slab_of(v[3 * (size_t)pts[i] + s->axis], s);
        if (runs && last[k] != SIZE_MAX && i - last[k] - 1 >= runs->min_gap[k] &&
            runs->n[k] < runs->cap)
            runs->at[(size_t)k * runs->cap + runs->n[k]++] = (uint32_t)(end[k] - begin[k]);
        last[k] = i;
        tmp[end[k]++] = pts[i];
    }
    memcpy(pts, tmp, np * sizeof *pts);
}

int kpar_slabs(const double *v, uint32_t *pts, size_t np, int nth, double *scratch,
               uint32_t *tmp, size_t begin[], size_t end[], kpar_slab_cuts *out)
{
    if (!kpar_slab_cuts_on(v, pts, np, nth, -1, scratch, out)) return 0;
    kpar_slab_split(v, pts, np, out, tmp, begin, end, NULL);
    return 1;
}

void kpar_crossing(const uint32_t *tv, size_t nt, size_t stride, const double *v,
                   const uint8_t *col, const kpar_slab_cuts s[3], int nth, size_t cross[4])
{
    size_t c0 = 0, c1 = 0, c2 = 0, c3 = 0;
    if (stride == 0) stride = 1;
#pragma omp parallel for num_threads(nth) schedule(static) reduction(+ : c0, c1, c2, c3)
    for (size_t t = 0; t < nt; t += stride) {
        const uint32_t *q = tv + 4 * t;
        if ((q[0] & KM_DEAD) || q[3] == KM_GHOST) continue;
        c0 += col[q[0]] != col[q[1]] || col[q[0]] != col[q[2]] || col[q[0]] != col[q[3]];
        int a[3] = {0, 0, 0};
        for (int d = 0; d < 3; d++) {
            const int k0 = kpar_slab_of(v[3 * (size_t)q[0] + d], &s[d]);
            for (int i = 1; i < 4; i++) a[d] |= kpar_slab_of(v[3 * (size_t)q[i] + d], &s[d]) != k0;
        }
        c1 += (size_t)a[0];
        c2 += (size_t)a[1];
        c3 += (size_t)a[2];
    }
    cross[0] = c0;
    cross[1] = c1;
    cross[2] = c2;
    cross[3] = c3;
}

int kpar_first_axis(const size_t cross[4])
{
    int best = 0;
    for (int d = 1; d < 3; d++)
        if (cross[1 + d] < cross[1 + best]) best = d;
    return cross[1 + best] * SLAB_FIRST_DEN < cross[0] * SLAB_FIRST_NUM ? best : -1;
}
