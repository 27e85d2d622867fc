/* build.h -- the kernel stage's entry point (prefix kbuild_): from the distinct points and
 * their insertion order to the result mesh's tets (see build.c). */
#ifndef GTET_BUILD_H
#define GTET_BUILD_H

#include <stddef.h>
#include <stdint.h>

#include "../base/base.h"
#include "../mesh/mesh.h"
#include "../pred/pred.h"

typedef struct kbuild_in {
    const uint32_t *order;   /* the insertion order: order[i] is the mesh vertex id of the i-th
                                point to insert (res->vertices, res->n_vertices of them) */
    const size_t *round_end; /* BRIO rounds: round r is order[round_end[r-1] .. round_end[r]) */
    int num_rounds;          /* <= 64 */
    uint64_t *keys;          /* NULL, or the BRIO's Moore keys along order with key_bits bits
                                per axis (sort_brio_keys): kbuild_run frees them */
    int key_bits;
    size_t first[4];         /* positions in order[] of the first tet's vertices (not coplanar:
                                kval_first_simplex) */
    int threads;             /* >= 1 */
    int degeneracies;        /* record the perturbation's decisions (gtet_options) */
    size_t degeneracy_limit;
    /* gtet_options.progress, called with the fraction of points inserted */
    void (*progress)(void *user, double fraction);
    void *progress_user;
    /* NULL, or called after each BRIO round with its record and wall seconds */
    void (*round_done)(void *user, int round, int num_rounds, const gtet_round_stats *rs,
                       double seconds);
    void *round_user;
    /* gtet_options.cancel: polled before each round and pass, and every 65536 points of a
     * serial pass (kpar); nonzero stops with GTET_ERR_CANCELLED */
    int (*cancel)(void *user);
    void *cancel_user;
    /* NULL, or the working mesh's growth guard (kmesh.h grow_guard) */
    gtet_status (*grow_guard)(void *user, size_t used_bytes, size_t cap_bytes, size_t min_bytes,
                              size_t *want_bytes);
    void *grow_user;
    int wide;                /* the tet arrays with room to widen them (kmesh.h wide) */
} kbuild_in;

/* From this many distinct points on, the kernel frees the result's vertices while its sorted
 * copy exists and scatters them back after compaction (NOTES.md E14): 24 bytes a point less
 * at a parallel run's peak, for a random scatter that costs ~10% of a 1M-point run at one
 * thread; below it the coordinates are held twice.  src/api/memory.c estimates with it. */
#define KBUILD_HOLD_ONCE_MIN ((size_t)1 << 24)

/* Insert the points of res (its vertices and n_points are set) in the order given, then
 * compact: fills res's tets (mesh vertex ids, positively oriented), neighbors, n_tets,
 * n_hull_facets, rounds, the degeneracy records and, in res->stats, pred (added to what it
 * holds), tets_created, walk_steps, walk_fallbacks, bytes_per_tet, peak_bytes, threads and
 * num_rounds.  *t_inserted receives omp_get_wtime() at the end of the insertion.  Every
 * callback runs on the calling thread, outside the parallel regions.  On failure res may be
 * partly filled (gtet_mesh_free frees it) and err (if not NULL) may hold details. */
gtet_status kbuild_run(const kbuild_in *in, gtet_mesh *res, double *t_inserted, gtet_error *err);

#endif
