/* rebalance.c -- the rebalancing of a round's first pass (NOTES.md E186; parallel.c
 * pass_parallel runs it): the untried rests of the threads' slices cut in two at Moore cell
 * boundaries, the colour boundaries moved back to the cuts (proofs/parallel.md O1), and the
 * threads' lists for the second region. */
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
