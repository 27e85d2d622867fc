/* rebalance.c -- the rebalancing of a round's first pass (NOTES.md E186, E258; parallel.c
 * pass_parallel runs it): the untried rests of the threads' slices cut in two at Moore cell
 * boundaries, or at their median coordinate across the slabs of a first pass on slabs, the
 * colour boundaries moved to the cuts (proofs/parallel.md O1), and the threads' lists for the
 * second region. */
#include "parallel.h"

#include <omp.h>
#include <string.h>

#include "../base/base.h"

/* The rebalancing of a round's first pass (NOTES.md E186).  The pass stopped when a thread had
 * inserted its whole slice; thread k left its rest L_k = pts[stop_at[k] .. end[k]) untried
 * (in key order: a tail of its slice along the curve).  Each rest is cut in two at a Moore
 * cell boundary: thread k keeps the first half, the next thread on the loop (k + 1 mod nth,
 * whose slice starts where L_k ends) takes the second half, and the colour boundary between
 * them moves back to the cut, so that both halves are their threads' (O1).  Thread k's list
 * in ti: its own first half, then (a run start, E100) the second half of L_{k-1}.  Returns 0
 * (nothing changed) when no rest is long enough to cut. */
int kpar_rebalance_cut(kpar *P, const uint64_t *pk, const uint32_t *pts, int nth,
                       const size_t end[], const size_t stop_at[], const uint64_t *keys, int sh,
                       size_t nmesh, size_t b2[], size_t e2[])
{
    size_t mid[256];
    uint64_t nb[256], cell[256];  /* the new boundaries, relative to the old bound0; the cuts' */
    int cut = 0;
    for (int k = 0; k < nth; k++) {
        mid[k] = end[k] - stop_at[k] >= KPAR_REBALANCE_MIN
                     ? kpar_rest_cut(pk, end[nth - 1], stop_at[k], end[k], &cell[k])
                     : end[k];
        cut |= mid[k] < end[k];
    }
    for (int k = 0; k < nth; k++)  /* an empty slice's range (kpar_slices): not cut here */
        if (P->cuts.rel[k] > KPAR_KEY_MASK) cut = 0;
    if (!cut) return 0;
    const uint64_t b0 = P->cuts.bound0;
    for (int k = 0; k < nth; k++) {
        const int p = (k + nth - 1) % nth;
        nb[k] = mid[p] < end[p] ? (cell[p] - b0) & KPAR_KEY_MASK : P->cuts.rel[k];
    }
    const uint64_t r0 = nb[0];
    P->cuts.bound0 = (b0 + r0) & KPAR_KEY_MASK;
    for (int k = 0; k < nth; k++) P->cuts.rel[k] = (nb[k] - r0) & KPAR_KEY_MASK;
    uint8_t *col = P->colour;
    const uint64_t *rel = P->cuts.rel, bound0 = P->cuts.bound0;
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t v = 0; v < nmesh; v++)
        col[v] = (uint8_t)kpar_colour_of((keys[v] << sh) & KPAR_KEY_MASK, rel, bound0, nth);
    uint32_t *ti = P->ti;
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        const int p = (k + nth - 1) % nth;
        b2[k] = at;
        memcpy(ti + at, pts + stop_at[k], (mid[k] - stop_at[k]) * sizeof *ti);
        at += mid[k] - stop_at[k];
        const size_t own = at - b2[k];
        memcpy(ti + at, pts + mid[p], (end[p] - mid[p]) * sizeof *ti);
        at += end[p] - mid[p];
        e2[k] = at;
        P->runs.n[k] = own > 0 && at > b2[k] + own;
        P->runs.at[(size_t)k * P->runs.cap] = (uint32_t)own;
    }
    for (int k = 0; GTET_DEBUG_ON && k < nth; k++)  /* O1: every point is its thread's */
        for (size_t i = b2[k]; i < e2[k]; i++) GTET_DEBUG_ASSERT(col[ti[i]] == k);
    return 1;
}

int kpar_rebalance_slabs(kpar *P, const uint32_t *pts, int nth, const size_t end[],
                         const size_t stop_at[], size_t nmesh, double *scratch, size_t b2[],
                         size_t e2[])
{
    const double *v = P->m->v;
    kpar_slab_cuts s = P->slab;
    const int ax = s.axis;
    /* give[k]: 1 thread k gives its rest's upper part to k + 1, -1 the last thread gives its
     * lower part to nth - 2, 0 nothing; med[k] the moved cut */
    int give[256] = {0}, cut = 0;
    double med[256];
    for (int k = 0; k < nth; k++) {
        if (end[k] - stop_at[k] < KPAR_REBALANCE_MIN) continue;
        /* the rest's median along the axis: its two-slab cut (refused when equal coordinates
         * would leave either side under a quarter of the rest) */
        kpar_slab_cuts half;
        if (!kpar_slab_cuts_on(v, pts + stop_at[k], end[k] - stop_at[k], 2, ax, scratch, &half))
            continue;
        const double m = half.cut[1];
        if (k < nth - 1) {
            /* the slab keeps a positive width (a cut never passes the one below it) */
            if (k > 0 && !(m > s.cut[k])) continue;
            give[k] = 1;
        } else {
            if (nth >= 2 && give[nth - 2]) continue;  /* that cut moves down already */
            if (!(m > s.cut[k])) continue;            /* nothing below the median to give */
            give[k] = -1;
        }
        med[k] = m;
        cut = 1;
    }
    if (!cut) return 0;
    for (int k = 0; k < nth; k++) {
        if (give[k] == 1) s.cut[k + 1] = med[k];
        if (give[k] == -1) s.cut[k] = med[k];
    }
    uint8_t *col = P->colour;
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t u = 0; u < nmesh; u++) col[u] = (uint8_t)kpar_slab_of(v[3 * u + ax], &s);
    /* the lists: thread k's kept points (its rest's points now of its slab), then the points
     * of its neighbours' rests now of its slab (a run start) */
    uint32_t *ti = P->ti;
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        b2[k] = at;
        for (size_t i = stop_at[k]; i < end[k]; i++)
            if (kpar_slab_of(v[3 * (size_t)pts[i] + ax], &s) == k) ti[at++] = pts[i];
        const size_t own = at - b2[k];
        for (int q = k - 1; q <= k + 1; q += 2) {
            if (q < 0 || q >= nth || !give[q]) continue;
            for (size_t i = stop_at[q]; i < end[q]; i++)
                if (kpar_slab_of(v[3 * (size_t)pts[i] + ax], &s) == k) ti[at++] = pts[i];
        }
        e2[k] = at;
        P->runs.n[k] = own > 0 && at > b2[k] + own;
        P->runs.at[(size_t)k * P->runs.cap] = (uint32_t)own;
    }
    size_t rests = 0;  /* every rest's point is in one list */
    for (int k = 0; k < nth; k++) rests += end[k] - stop_at[k];
    GTET_DEBUG_ASSERT(at == rests);
    (void)rests;
    for (int k = 0; GTET_DEBUG_ON && k < nth; k++)  /* O1: every point is its thread's */
        for (size_t i = b2[k]; i < e2[k]; i++) GTET_DEBUG_ASSERT(col[ti[i]] == k);
    P->slab = s;
    return 1;
}
