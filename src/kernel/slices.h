/* slices.h -- the cuts of a parallel pass into one slice per thread and the colour ranges of
 * the vertices (prefix kpar_); see slices.c.  Used by parallel.c and exposed for the tests of
 * obligation O1 (proofs/parallel.md): every point of slice k has colour k. */
#ifndef GTET_SLICES_H
#define GTET_SLICES_H

#include <stddef.h>
#include <stdint.h>

#define KPAR_KEY_BITS 21                         /* per axis */
#define KPAR_KEY_MASK ((UINT64_C(1) << 63) - 1)  /* 63-bit Moore keys, 21 bits per axis */

/* A pass's colour ranges (kpar_colour_of), kept for the next pass's cuts. */
typedef struct kpar_cuts {
    uint64_t rel[256];
    uint64_t bound0;
    int nth;
} kpar_cuts;

/* Cut the sorted pending keys pk[0..np) (pts alongside; both may be rotated cyclically) into
 * nth slices [begin[k], end[k]) and colour ranges rel[], bound0 (kpar_colour_of); rotate: 0
 * cuts from the first key, 1 half a slice further along the loop (a round's first retry), 2
 * from the origin whose cuts are coarsest (a round's first pass).  prev: NULL, or with rotate
 * 1 the previous pass's ranges (on the same keys), whose slices' middles the cuts then take.
 * Slices of equal counts before the snapping (NOTES.md E188 ended the cost weights of E21).
 * tk, ti: scratch of np entries each. */
void kpar_slices(uint64_t *pk, uint32_t *pts, size_t np, int nth, int rotate,
                 const kpar_cuts *prev, uint64_t *tk, uint32_t *ti,
                 size_t begin[], size_t end[], uint64_t rel[], uint64_t *bound0);

/* The rebalancing's cut of a rest pk[lo..hi) of the sorted keys pk[0..np) (0 <= lo, hi - lo >= 2):
 * the position i (lo < i < hi) of the coarsest Moore-cell gap near the rest's middle, its
 * cell's key B (pk[i - 1] < B <= pk[i] along the loop) in *bound; hi when none (slices.c). */
size_t kpar_rest_cut(const uint64_t *pk, size_t np, size_t lo, size_t hi, uint64_t *bound);

/* The colour of a vertex with 63-bit key `key`: the largest k with rel[k] <= key measured from
 * bound0 along the loop. */
static inline int kpar_colour_of(uint64_t key, const uint64_t rel[], uint64_t bound0, int nth)
{
    const uint64_t k = (key - bound0) & KPAR_KEY_MASK;
    int c = nth - 1;
    while (c > 0 && k < rel[c]) c--;
    return c;
}

#endif
