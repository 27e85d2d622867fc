/* finalize.c -- turn the working mesh into the result object, in place.
 *
 * Live finite tets are renumbered in slot order and moved down in place (a tet only ever moves
 * to a lower slot, which has already been read), their neighbour handles 4u+j become tet ids
 * (GTET_NO_TET across a hull facet, i.e. towards a ghost), and the arrays are shrunk.  The
 * peak is the working mesh plus one uint32 per slot for the renumbering.
 */
#include "finalize.h"

#include <stdlib.h>

gtet_status km_finalize(kmesh *m, uint32_t **tets, uint32_t **nbrs, size_t *ntets,
                        size_t *nhull)
{
    size_t nt = m->nt, live = 0, hull = 0;
    uint32_t *newidx = malloc((nt ? nt : 1) * sizeof *newidx);
    if (!newidx) return GTET_ERR_OUT_OF_MEMORY;
    for (size_t t = 0; t < nt; t++) {
        if (m->tf[t] & KM_DELETED) {
            newidx[t] = GTET_NO_TET;
        } else if (m->tv[4 * t + 3] == KM_GHOST) {
            newidx[t] = GTET_NO_TET;
            hull++;
        } else {
            newidx[t] = (uint32_t)live++;
        }
    }
    for (size_t t = 0; t < nt; t++) {
        uint32_t d = newidx[t];
        if (d == GTET_NO_TET) continue;
        for (int f = 0; f < 4; f++) {
            uint32_t h = m->tn[4 * t + (size_t)f];
            m->tv[4 * (size_t)d + (size_t)f] = m->tv[4 * t + (size_t)f];
            m->tn[4 * (size_t)d + (size_t)f] = newidx[h >> 2];
        }
    }
    free(newidx);
    uint32_t *tv = m->tv, *tn = m->tn;
    if (live) {
        uint32_t *a = realloc(tv, 4 * live * sizeof *a);
        if (a) tv = a;
        uint32_t *b = realloc(tn, 4 * live * sizeof *b);
        if (b) tn = b;
    }
    free(m->tf);
    m->tf = NULL;
    m->tv = NULL;
    m->tn = NULL;
    m->cap = m->nt = 0;
    *tets = tv;
    *nbrs = tn;
    *ntets = live;
    *nhull = hull;
    return GTET_OK;
}
