/* starts.h -- where a thread of a parallel pass starts and restarts walking (prefix kpar_):
 * tets of its own colour located read-only before the pass's barrier (proofs/parallel.md O4);
 * see starts.c. */
#ifndef GTET_STARTS_H
#define GTET_STARTS_H

#include "kmesh.h"

#define KPAR_CK_MAX 256  /* checkpoints a slice at most */

/* Where a thread may walk on from, found before the pass's barrier (O4): the checkpoints
 * (E13) and a tet for each run start of its slab (E100).  During the pass only this thread
 * writes such a slot: it is its tet, which no other thread may kill, and once killed the slot
 * is on its free list. */
typedef struct kpar_restarts {
    uint32_t ck[KPAR_CK_MAX];
    int nck;
    const uint32_t *run_at;  /* kpar.runs: offsets in the slice, increasing */
    uint32_t *run_tet;       /* per run start: a tet of this thread, or UINT32_MAX */
    size_t nruns;
} kpar_restarts;

/* A live tet of this thread's colour to start the slice pts[0..np) from, in c->last; 0 when
 * the thread has none. */
int kpar_find_start(kctx *c, int nthreads, const uint32_t *pts, size_t np);

/* The number of checkpoints of a slice of np points (64 to KPAR_CK_MAX). */
int kpar_checkpoints(size_t np);

/* ck[0..nck): restart tets along the slice (E13), UINT32_MAX where none was found. */
void kpar_find_checkpoints(kctx *c, const uint32_t *pts, size_t np, int nck, uint32_t ck[]);

/* R->run_tet[0..R->nruns): a tet of this thread for each run start of a slab pass (E100). */
void kpar_find_runs(kctx *c, const uint32_t *pts, size_t np, kpar_restarts *R);

/* hint[v] for the slice's points v = pts[0..np): kept where it is a live tet of this thread,
 * else UINT32_MAX (E177); the slice's points are this thread's, so it alone writes them. */
void kpar_check_hints(kctx *c, const uint32_t *pts, size_t np, uint32_t *hint);

#endif
