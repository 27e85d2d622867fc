/* parallel.h -- concurrent insertion of BRIO rounds on Moore-curve partitions (prefix kpar_);
 * see parallel.c. */
#ifndef GTET_PARALLEL_H
#define GTET_PARALLEL_H

#include "mesh.h"

typedef struct kpar {
    kmesh *m;
    kctx *ctx;          /* one per thread */
    int threads;
    double bbox[6];     /* tight box of all vertices */
    uint8_t *colour;    /* per vertex, valid during a pass */
    uint64_t *keys;     /* per vertex, Moore keys on the tight box (computed once) */
    int have_keys;
    uint64_t *skeys;    /* per vertex in the mesh, keys on a later pass's shifted box */
    uint64_t *pk, *tk;  /* pending points' keys and radix scratch */
    uint32_t *ti;
    size_t cap_pending;
    /* progress: done / total points, reported from the calling thread */
    void (*progress)(void *user, double fraction);
    void *progress_user;
    size_t done, total;
} kpar;

gtet_status kpar_init(kpar *P, kmesh *m, kctx *ctx, int threads);
void kpar_free(kpar *P);

/* Insert the points pts[0..np) (a BRIO round; the array is reordered) with up to P->threads
 * threads, filling the round's statistics. */
gtet_status kpar_round(kpar *P, uint32_t *pts, size_t np, gtet_round_stats *rs);

#endif
