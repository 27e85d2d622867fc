/* mpi_internal.h -- shared pieces of gigatet's distributed mode (src/mpi/), not public.
 * Built only on the public API (gigatet.h) and MPI. */
#ifndef GTET_MPI_INTERNAL_H
#define GTET_MPI_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "gigatet_mpi.h"

/* A point with its global vertex id (or, before the ids exist, its global input index). */
typedef struct mpt {
    double x[3];
    uint64_t id;
} mpt;

/* One rank's view of a collective run. */
typedef struct mctx {
    MPI_Comm comm;
    int rank, size;
    gtet_error err;          /* this rank's error, then the agreed one */
    gtet_mpi_stats *st;
    int *sc, *sd, *rc, *rd;  /* 4 * size ints for the all-to-all exchanges */
} mctx;

/* Allocation with an optional injected failure (tests only): see gtet_mpi_debug_fail_alloc. */
void *mx_malloc(size_t bytes);
void *mx_calloc(size_t count, size_t size);
void *mx_realloc(void *p, size_t bytes);

/* Fault injection for the tests: on this process, the `after`-th allocation of the
 * distributed layer from now on fails (0 = the next one; negative = never).  Not thread-safe;
 * the distributed layer allocates from the calling thread only. */
void gtet_mpi_debug_fail_alloc(long after);

/* Set this rank's error (first one wins); returns status. */
gtet_status mx_fail(mctx *c, gtet_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Collective: agree on a status.  Returns GTET_OK when every rank passed GTET_OK, else the
 * error of the lowest failing rank, whose gtet_error is copied to every rank's c->err. */
gtet_status mx_agree(mctx *c, gtet_status mine);

/* Collective all-to-all of records of `rsize` bytes: scnt[q] records to rank q, sent from
 * sbuf in rank order.  On success *rbuf (malloc'ed, never NULL) holds rcnt[q] records from
 * each q in rank order, *rtot in all.  Errors (counts over INT_MAX, allocation) are agreed
 * on.  `ghost`: count the bytes as ghost traffic too. */
gtet_status mx_exchange(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                        void **rbuf, size_t *rcnt, size_t *rtot, int ghost);

double mx_now(void);

/* qsort of n elements; nothing at all for n < 2, so an empty array may be NULL (the C library's
 * qsort requires a valid pointer even for n == 0). */
static inline void mpi_sort(void *p, size_t n, size_t size, int (*cmp)(const void *, const void *))
{
    if (n > 1) qsort(p, n, size, cmp);
}

#endif
