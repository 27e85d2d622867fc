/* finalize.c -- turn the working mesh into the result object, in place.
 *
 * Live finite tets are renumbered in slot order, their neighbour handles 4u+j become tet ids
 * (GTET_NO_TET across a hull facet, i.e. towards a ghost), they are moved down in place, and
 * the arrays are shrunk.  With T threads the slots are cut into T chunks:
 *   1. each chunk counts its live finite tets; a prefix sum gives each chunk its first new id,
 *      and each chunk writes the new ids of its slots (newidx);
 *   2. each chunk copies its live tets, translated, to the front of its own slot range, in
 *      slot order (a tet only moves down inside its chunk, to a slot already read);
 *   3. the chunks' blocks are moved down to their final places, in chunk order (memmove).
 * Steps 1 and 2 run in parallel: a thread writes only its own chunk's slots and newidx
 * entries, and reads other chunks' newidx only after the barrier that ends step 1.  The result
 * does not depend on T.  The peak is the working mesh plus one uint32 per slot (newidx).  The
 * dead bit lives in tv[4t] and is never set on a live tet, so live vertex ids are copied as
 * they are.
 */
#include "finalize.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define FIN_MAX_THREADS 256
#define FIN_MIN_CHUNK 65536  /* fewer slots per thread: fewer threads */

gtet_status km_finalize(kmesh *m, uint32_t **tets, uint32_t **nbrs, size_t *ntets,
                        size_t *nhull, int threads)
{
    const size_t nt = m->nt;
    uint32_t *newidx = malloc((nt ? nt : 1) * sizeof *newidx);
    if (!newidx) return GTET_ERR_OUT_OF_MEMORY;
    int T = threads < 1 ? 1 : threads > FIN_MAX_THREADS ? FIN_MAX_THREADS : threads;
    while (T > 1 && nt / (size_t)T < FIN_MIN_CHUNK) T--;
    size_t lo[FIN_MAX_THREADS + 1], live_in[FIN_MAX_THREADS], hull_in[FIN_MAX_THREADS];
    size_t base[FIN_MAX_THREADS];
    for (int k = 0; k <= T; k++) lo[k] = nt / (size_t)T * (size_t)k;
    lo[T] = nt;
    uint32_t *tv = m->tv, *tn = m->tn;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        const int k = omp_get_thread_num();
        size_t live = 0, hull = 0;
        for (size_t t = lo[k]; t < lo[k + 1]; t++) {
            if (km_dead(m, t)) continue;
            if (tv[4 * t + 3] == KM_GHOST) hull++;
            else live++;
        }
        live_in[k] = live;
        hull_in[k] = hull;
#pragma omp barrier
#pragma omp single
        {
            size_t sum = 0;
            for (int j = 0; j < T; j++) {
                base[j] = sum;
                sum += live_in[j];
            }
        }
        uint32_t next = (uint32_t)base[k];
        for (size_t t = lo[k]; t < lo[k + 1]; t++)
            newidx[t] = km_dead(m, t) || tv[4 * t + 3] == KM_GHOST ? GTET_NO_TET : next++;
#pragma omp barrier
        size_t d = lo[k];
        for (size_t t = lo[k]; t < lo[k + 1]; t++) {
            if (newidx[t] == GTET_NO_TET) continue;
            uint32_t n[4];
            for (int f = 0; f < 4; f++) n[f] = newidx[tn[4 * t + (size_t)f] >> 2];
            memmove(tv + 4 * d, tv + 4 * t, 4 * sizeof *tv);
            memcpy(tn + 4 * d, n, sizeof n);
            d++;
        }
    }
    free(newidx);
    size_t live = 0, hull = 0;
    for (int k = 0; k < T; k++) {
        if (base[k] != lo[k] && live_in[k]) {
            memmove(tv + 4 * base[k], tv + 4 * lo[k], 4 * live_in[k] * sizeof *tv);
            memmove(tn + 4 * base[k], tn + 4 * lo[k], 4 * live_in[k] * sizeof *tn);
        }
        live += live_in[k];
        hull += hull_in[k];
    }
    if (live) {
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
