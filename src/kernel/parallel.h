/* parallel.h -- concurrent insertion of BRIO rounds on Moore-curve partitions (prefix kpar_);
 * see parallel.c. */
#ifndef GTET_PARALLEL_H
#define GTET_PARALLEL_H

#include "kmesh.h"
#include "slabs.h"
#include "slices.h"

typedef struct kpar {
    kmesh *m;
    kctx *ctx;          /* one per thread */
    int threads;
    uint8_t *colour;    /* per vertex, valid during a pass */
    uint64_t *keys;     /* per vertex, Moore keys of the first two passes of a round: the
                         * BRIO's (key_shift = 63 - 3 bits: its keys are prefixes of 21-bit
                         * ones) or, when the BRIO gave none, on the tight box with 21 bits
                         * (computed once, key_shift 0); a vertex's 63-bit key is
                         * (keys[v] << key_shift) & KPAR_KEY_MASK (pass_parallel) */
    int key_shift;
    int have_keys;
    int own3;           /* passes use three-of-four ownership (after a failed pass, kpar_round) */
    kpar_cuts cuts;     /* the last parallel pass's colour ranges (the first retry's cuts) */
    kpar_slab_cuts slab; /* a round's first pass on slabs: its cuts (the rebalancing's), and */
    int slab_first;      /* nonzero while that pass runs (partition.c) */
    uint64_t *skeys;    /* per vertex in the mesh, keys on a later pass's shifted box */
    kpar_runs runs;     /* a slab pass's run starts per slice (slabs.h, NOTES.md E100); n[k]
                         * 0 in a pass on Moore slices */
    uint32_t *run_tet;  /* per run start: a tet of the slice's thread located before the pass */
    uint32_t *hint;     /* per vertex, with threads: where a deferred point's next walk starts
                         * (kctx.defer_hint), UINT32_MAX for none; written for a round's
                         * pending points only, read from its second pass on (E177) */
    uint64_t *pk, *tk;  /* pending points' keys and radix scratch */
    uint32_t *ti;
    size_t cap_pending;
    /* progress: done / total points, reported from the calling thread; done is also the number
     * of vertices in the mesh (the first tet's four and every point inserted), which the first
     * pass's crossing sample is sized by (partition.c) */
    void (*progress)(void *user, double fraction);
    void *progress_user;
    size_t done, total;
    /* gtet_options.cancel, polled from the calling thread before each pass and every 65536
     * points of a serial pass; nonzero stops the round with GTET_ERR_CANCELLED (the mesh is
     * left mid-round, and kbuild_release frees it whole) */
    int (*cancel)(void *user);
    void *cancel_user;
} kpar;

/* keys: NULL, or the BRIO's keys of the vertices in internal order with key_bits bits per
 * axis (sort_brio_keys), which P then owns (kpar_free frees them, also after a failure). */
gtet_status kpar_init(kpar *P, kmesh *m, kctx *ctx, int threads, uint64_t *keys, int key_bits);
void kpar_free(kpar *P);

/* The slices pts[begin[k] .. end[k]) of a pass over pts[0..np) (reordered) and the colours of
 * the vertices 0..nmesh-1 (O1); *keys_out and *sh_out: the Moore keys the slices were cut on
 * (a vertex's key (keys[v] << sh) & KPAR_KEY_MASK), NULL for slabs (partition.c). */
void kpar_pass_partition(kpar *P, uint32_t *pts, size_t np, size_t nmesh, int nth, unsigned pass,
                         size_t begin[], size_t end[], const uint64_t **keys_out, int *sh_out);

/* A round's first pass stops once a thread has done its slice; a thread then leaves the rest
 * of its slice to the rebalancing only when at least this many points are left, else it goes
 * on: a shorter rest costs less than the rebalancing's barrier, recolouring and new cut
 * (NOTES.md E186). */
#define KPAR_REBALANCE_MIN 4096

/* The rebalancing's cuts (rebalance.c; parallel.c pass_parallel): thread k left its slice's
 * rest pts[stop_at[k] .. end[k]) (pk alongside, the pass's keys and colour ranges in P->cuts);
 * each rest of at least KPAR_REBALANCE_MIN points is cut in two, the next thread takes the
 * second half, the vertices 0..nmesh-1 are recoloured by the moved boundaries (their keys
 * (keys[v] << sh) & KPAR_KEY_MASK), and thread k's list is P->ti[b2[k] .. e2[k]) (its own first
 * half, then the taken half from a run start in P->runs).  0, nothing changed, when no rest
 * could be cut. */
int kpar_rebalance_cut(kpar *P, const uint64_t *pk, const uint32_t *pts, int nth,
                       const size_t end[], const size_t stop_at[], const uint64_t *keys, int sh,
                       size_t nmesh, size_t b2[], size_t e2[]);

/* The same for a round's first pass on slabs (P->slab; NOTES.md E258): thread k < nth - 1
 * with a rest of at least KPAR_REBALANCE_MIN points gives thread k + 1 the rest's points at or
 * above their median coordinate along the slabs' axis (kpar_slab_cuts_on with two slabs: not
 * where equal coordinates leave a side under a quarter), and the cut between the two slabs moves
 * down to that median; the last thread gives thread nth - 2 the points below its rest's median
 * (the cut moving up) when thread nth - 2 gave nothing.  The vertices 0..nmesh-1 are
 * recoloured by the new cuts; thread k's list is P->ti[b2[k] .. e2[k]) (what it kept of its
 * rest, then the points it took, from a run start in P->runs), each part in the pass's order.
 * scratch: the rests' coordinates (np doubles).  0, nothing changed, when no rest was cut. */
int kpar_rebalance_slabs(kpar *P, const uint32_t *pts, int nth, const size_t end[],
                         const size_t stop_at[], size_t nmesh, double *scratch, size_t b2[],
                         size_t e2[]);

/* Tests only (0 in every run of the library): when nonzero, thread 0 of a round's first pass
 * (on Moore slices or slabs) signals the stop of the rebalancing (parallel.c pass_parallel)
 * after this many tries, so that every thread leaves a rest to cut. */
extern size_t kpar_test_stop_after;

/* Insert the points pts[0..np) (a BRIO round; the array is reordered) with up to P->threads
 * threads, filling the round's statistics. */
gtet_status kpar_round(kpar *P, uint32_t *pts, size_t np, gtet_round_stats *rs);

#endif
