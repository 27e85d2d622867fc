/* finalize.c -- turn the working mesh into the result object, in place.
 *
 * The output is the L live finite tets in slots 0..L-1, with neighbour ids instead of the
 * kernel's handles 4u+j and GTET_NO_TET across a hull facet.  At the end of an insertion
 * almost every slot holds a live finite tet (1M uniform points: 0 deleted slots and 558 ghosts
 * in 6.75M slots; a 100^3 grid: 117,612 ghosts in 5.94M), so the slots are compacted by
 * filling holes, not by renumbering them all:
 *   1. (parallel, T chunks of the slots) count the live finite tets of each chunk, list the
 *      chunk's other slots (deleted or ghost: the holes), and mark the finite facet of every
 *      live ghost on its finite neighbour: that neighbour's handle becomes KM_HULL; with a
 *      map, write each live finite tet's vertices as the caller's ids (the pass reads those
 *      lines anyway: a separate pass over the tets took as long as the compaction, NOTES.md
 *      E256; a mapped id is below 2^31, so it never reads as a dead mark or as KM_GHOST);
 *   2. (serial) L = the number of live finite tets; the holes below L are paired, in order,
 *      with the live finite tets at or above L (there are as many of each); each such tet is
 *      copied into its hole and its four neighbours' back handles are pointed at the new slot
 *      (tn[h] = 4i+f: a back handle is the slot it must change, so this is O(1) per facet);
 *   3. (parallel) every handle of slots 0..L-1 becomes its tet id (h >> 2), KM_HULL becomes
 *      GTET_NO_TET; the arrays are shrunk to L tets.
 * Work: two streaming passes over the slots plus O(holes) random accesses; no array of one
 * entry per slot (renumbering every slot through one is slower: NOTES.md D6).  A
 * handle of a live finite tet never names a deleted slot, and after step 1 never a ghost, so
 * step 2 only touches live finite tets: a neighbour that has not been moved yet gets its back
 * handle fixed in place and carries it when it moves.  KM_HULL = UINT32_MAX is not a handle:
 * the slots are fewer than 2^30 (kmesh.h KM_MAX_SLOTS), so 4u+j <= 2^32 - 5.  The result
 * does not depend on T (step 2 is serial and steps 1 and 3 are per slot).
 */
#include "finalize.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define FIN_MAX_THREADS 256
#define FIN_MIN_CHUNK 65536  /* fewer slots per thread: fewer threads */
#define KM_HULL UINT32_MAX

_Static_assert(4 * ((uint64_t)KM_MAX_SLOTS - 1) + 3 < KM_HULL, "KM_HULL must not be a handle");
_Static_assert(KM_HULL == GTET_NO_TET, "step 3 keeps KM_HULL as GTET_NO_TET");

/* one chunk's holes, in slot order */
typedef struct {
    uint32_t *at;
    size_t n, cap;
    int oom;
} fin_holes;

static void holes_push(fin_holes *h, uint32_t t)
{
    if (h->n == h->cap) {
        const size_t cap = h->cap ? 2 * h->cap : 1024;
        uint32_t *a = realloc(h->at, cap * sizeof *a);
        if (!a) {
            h->oom = 1;
            return;
        }
        h->at = a;
        h->cap = cap;
    }
    h->at[h->n++] = t;
}

gtet_status km_finalize(kmesh *m, uint32_t **tets, uint32_t **nbrs, size_t *ntets,
                        size_t *nhull, int threads, const uint32_t *map)
{
    const size_t nt = m->nt;
    int T = threads < 1 ? 1 : threads > FIN_MAX_THREADS ? FIN_MAX_THREADS : threads;
    while (T > 1 && nt / (size_t)T < FIN_MIN_CHUNK) T--;
    size_t lo[FIN_MAX_THREADS + 1], live_in[FIN_MAX_THREADS], hull_in[FIN_MAX_THREADS];
    fin_holes holes[FIN_MAX_THREADS];
    memset(holes, 0, (size_t)T * sizeof holes[0]);
    for (int k = 0; k <= T; k++) lo[k] = nt / (size_t)T * (size_t)k;
    lo[T] = nt;
    uint32_t *tv = m->tv, *tn = m->tn;

    /* 1. count, list the holes, mark the hull facets */
#pragma omp parallel num_threads(T) if (T > 1)
    {
        const int k = omp_get_thread_num();
        size_t live = 0, hull = 0;
        fin_holes *h = &holes[k];
        for (size_t t = lo[k]; t < lo[k + 1]; t++) {
            if (km_dead(m, t)) {
                holes_push(h, (uint32_t)t);
            } else if (tv[4 * t + 3] == KM_GHOST) {
                hull++;
                holes_push(h, (uint32_t)t);
                tn[tn[4 * t + 3]] = KM_HULL;  /* the finite tet's facet on the hull */
            } else {
                live++;
                if (map)
                    for (int i = 0; i < 4; i++) tv[4 * t + i] = map[tv[4 * t + i]];
            }
        }
        live_in[k] = live;
        hull_in[k] = hull;
    }
    size_t live = 0, hull = 0;
    int oom = 0;
    for (int k = 0; k < T; k++) {
        live += live_in[k];
        hull += hull_in[k];
        oom |= holes[k].oom;
    }
    if (oom) {
        /* the hull marks cannot be undone cheaply; the mesh is dropped by the caller */
        for (int k = 0; k < T; k++) free(holes[k].at);
        return GTET_ERR_OUT_OF_MEMORY;
    }

    /* 2. fill the holes below L with the live finite tets at or above L */
    size_t src = live;
    for (int k = 0; k < T; k++) {
        for (size_t q = 0; q < holes[k].n; q++) {
            const size_t i = holes[k].at[q];
            if (i >= live) break;  /* lists are in slot order, chunks in chunk order */
            while (km_dead(m, src) || tv[4 * src + 3] == KM_GHOST) src++;
            memcpy(tv + 4 * i, tv + 4 * src, 4 * sizeof *tv);
            memcpy(tn + 4 * i, tn + 4 * src, 4 * sizeof *tn);
            for (uint32_t f = 0; f < 4; f++) {
                const uint32_t b = tn[4 * i + f];
                if (b != KM_HULL) tn[b] = 4 * (uint32_t)i + f;
            }
            src++;
        }
        free(holes[k].at);
    }

    /* 3. handles -> tet ids */
    const size_t n4 = 4 * live;
#pragma omp parallel for num_threads(T) schedule(static) if (T > 1)
    for (size_t i = 0; i < n4; i++) tn[i] = tn[i] == KM_HULL ? GTET_NO_TET : tn[i] >> 2;

    if (live && !m->wide) {  /* wide: handed over with their room (kmesh.h) */
        uint32_t *a = realloc(tv, 4 * live * sizeof *a);
        if (a) tv = a;
        uint32_t *b = realloc(tn, 4 * live * sizeof *b);
        if (b) tn = b;
    }
    m->tv = NULL;
    m->tn = NULL;
    m->cap = m->nt = 0;
    *tets = tv;
    *nbrs = tn;
    *ntets = live;
    *nhull = hull;
    return GTET_OK;
}
