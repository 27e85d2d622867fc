/* finalize.h -- compaction of the working mesh into the output arrays (see finalize.c). */
#ifndef GTET_FINALIZE_H
#define GTET_FINALIZE_H

#include "kmesh.h"

/* Hands the mesh's tv/tn arrays over as *tets / *nbrs (finite tets only, GTET_NO_TET on the
 * hull; shrunk to them by realloc unless m->wide) and empties m; up to `threads` threads (same
 * result for any count).  map: NULL, or the vertex ids the tets are written with (vertex v of
 * the mesh becomes map[v], every map[v] < 2^31). */
gtet_status km_finalize(kmesh *m, uint32_t **tets, uint32_t **nbrs, size_t *ntets,
                        size_t *nhull, int threads, const uint32_t *map);

#endif
