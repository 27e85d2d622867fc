/* mpi_util.c -- error agreement, all-to-all exchanges, the allocation hook and the small
 * containers (a hash set of ids, a growable record vector) of the distributed mode.  Every
 * collective error path goes through mx_agree, so a failure on one rank makes every rank leave
 * the same step with the same status: no rank waits in a collective another rank never
 * enters. */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/base.h"
#include "mesh/mesh.h"
#include "mpi/mpi_internal.h"

static long fail_countdown = -1;

void gtet_mpi_debug_fail_alloc(long after) { fail_countdown = after; }

static int injected(void)
{
    if (fail_countdown < 0) return 0;
    if (fail_countdown == 0) {
        fail_countdown = -1;
        return 1;
    }
    fail_countdown--;
    return 0;
}

/* blocks of this size and more start on a 2 MiB boundary and get the pages the kernel's big
 * arrays get (base_alloc_huge, base_page_mode): huge pages where a 4 KiB fault is costly (a
 * rank writes its big arrays -- the exchanges' buffers, the patched mesh, the result -- once
 * each, afresh: NOTES E50), 4 KiB pages where the host takes free memory back and a 4 KiB
 * fault is cheap, as for the kernel (NOTES E163; the MPI layer on such a host: D82) */
#define MX_HUGE_MIN ((size_t)8 << 20)

void *mx_malloc(size_t bytes)
{
    if (injected()) return NULL;
    if (bytes >= MX_HUGE_MIN) return base_alloc_huge(bytes);
    return malloc(bytes ? bytes : 1);
}

void *mx_calloc(size_t count, size_t size)
{
    if (injected()) return NULL;
    if (count == 0 || size == 0) return calloc(1, 1);
    return calloc(count, size);
}

void *mx_realloc(void *p, size_t bytes)
{
    if (injected()) return NULL;
    return realloc(p, bytes ? bytes : 1);
}

void mx_free_input(void *user)
{
    double **p = user;
    free(*p);
    *p = NULL;
}

gtet_status mx_triangulate_own(const gtet_options *lopt, double *xyz, size_t n, gtet_mesh **out,
                               gtet_error *e)
{
    memset(e, 0, sizeof *e);
    gtet_options o = *lopt;
    o.error = e;
    o.input_done = mx_free_input;
    o.input_done_user = &xyz;
    gtet_status s = gtet_triangulate_wide_distinct(xyz, n, &o, out);
    free(xyz);  /* NULL once the kernel has called input_done */
    return s;
}

double mx_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

gtet_status mx_fail(mctx *c, gtet_status status, const char *fmt, ...)
{
    if (c->err.status != GTET_OK) return c->err.status;
    c->err.status = status;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->err.message, sizeof c->err.message, fmt, ap);
    va_end(ap);
    return status;
}

/* MPI_Wait that gives the CPU back while it waits: a rank that finished its part first (the
 * tiles' triangulations differ by 5-10 %) would otherwise spin in Open MPI's progress loop
 * (busy polling: 10 % of a rank's instructions at 250k points, np 2), on a CPU the other rank
 * or another job could use.  Tests for ~20 us first (a prompt answer costs no sleep), then
 * sleeps between tests: 50 us, each nap a quarter longer than the last up to 1 ms, so that a
 * wait of a few hundred ms (the other rank's longer triangulation) wakes a few hundred times,
 * not thousands (each wake-up a system call and two context switches: NOTES.md E229); an
 * answer is seen at most one nap late. */
#define WAIT_NAP_MIN_NS 50000L
#define WAIT_NAP_MAX_NS 1000000L
void mx_wait(MPI_Request *rq)
{
    int done = 0;
    double t0 = mx_now();
    MPI_Test(rq, &done, MPI_STATUS_IGNORE);
    while (!done && mx_now() - t0 < 20e-6) MPI_Test(rq, &done, MPI_STATUS_IGNORE);
    struct timespec nap = {0, WAIT_NAP_MIN_NS};
    while (!done) {
        nanosleep(&nap, NULL);
        MPI_Test(rq, &done, MPI_STATUS_IGNORE);
        nap.tv_nsec += nap.tv_nsec / 4;
        if (nap.tv_nsec > WAIT_NAP_MAX_NS) nap.tv_nsec = WAIT_NAP_MAX_NS;
    }
}

/* Zero the upper halves of the vector registers (vzeroupper) where the CPU has AVX.  The ABI
 * says they are clean at every call, and nothing here holds a value in them across this call;
 * but on this project's machine the SSE code after the kernel and the MPI calls ran up to 1.6x
 * slower in the ranks that had not since run code ending in vzeroupper (NOTES.md E220, Q53):
 * some code before leaves them dirty.  Speed only; no result depends on it. */
void mx_upper_clean(void)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (__builtin_cpu_supports("avx")) __asm__ volatile("vzeroupper" ::: "memory");
#endif
}

gtet_status mx_agree(mctx *c, gtet_status mine)
{
    if (mine != GTET_OK && c->err.status == GTET_OK) {
        c->err.status = mine;
        snprintf(c->err.message, sizeof c->err.message, "rank %d: %s", c->rank,
                 gtet_status_str(mine));
    }
    int me = mine != GTET_OK ? c->rank : c->size, low = c->size;
    MPI_Request rq;
    MPI_Iallreduce(&me, &low, 1, MPI_INT, MPI_MIN, c->comm, &rq);
    mx_wait(&rq);
    if (low == c->size) return GTET_OK;
    /* gtet_error is plain data: the lowest failing rank's copy goes to everyone */
    MPI_Bcast(&c->err, (int)sizeof c->err, MPI_BYTE, low, c->comm);
    return c->err.status;
}

/* mx_exchange, and with `keep` mx_exchange_keep */
static gtet_status exchange(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                            void **rbuf, size_t *rcnt, size_t *rtot, int ghost, int keep)
{
    *rbuf = NULL;
    *rtot = 0;
    int P = c->size, me = c->rank;
    gtet_status s = GTET_OK;
    size_t tot = 0;
    for (int q = 0; q < P; q++) {
        if (scnt[q] > (size_t)INT_MAX || tot > (size_t)INT_MAX - scnt[q]) {
            s = mx_fail(c, GTET_ERR_TOO_LARGE,
                        "rank %d would send more than 2^31-1 records of %zu bytes in one exchange",
                        c->rank, rsize);
            break;
        }
        c->sc[q] = keep && q == me ? 0 : (int)scnt[q];
        c->sd[q] = (int)tot;
        tot += (size_t)c->sc[q];
    }
    if ((s = mx_agree(c, s)) != GTET_OK) return s;
    MPI_Alltoall(c->sc, 1, MPI_INT, c->rc, 1, MPI_INT, c->comm);
    if (keep) c->rc[me] = (int)scnt[me];   /* room for them; not transferred */
    size_t rt = 0;
    for (int q = 0; q < P; q++) {
        rcnt[q] = (size_t)c->rc[q];
        if (rt > (size_t)INT_MAX - rcnt[q]) {
            s = mx_fail(c, GTET_ERR_TOO_LARGE,
                        "rank %d would receive more than 2^31-1 records in one exchange", c->rank);
            break;
        }
        c->rd[q] = (int)rt;
        rt += rcnt[q];
    }
    void *buf = NULL;
    if (s == GTET_OK) {
        buf = mx_malloc(rt * rsize);
        if (!buf)
            s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY,
                        "rank %d: out of memory receiving %zu records", c->rank, rt);
    }
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(buf);
        return s;
    }
    MPI_Datatype t;
    MPI_Type_contiguous((int)rsize, MPI_BYTE, &t);
    MPI_Type_commit(&t);
    static const char dummy[1];
    if (keep) c->rc[me] = 0;
    MPI_Alltoallv(sbuf ? sbuf : dummy, c->sc, c->sd, t, buf, c->rc, c->rd, t, c->comm);
    MPI_Type_free(&t);
    uint64_t bytes = 0;
    for (int q = 0; q < P; q++)
        if (q != c->rank) bytes += (uint64_t)scnt[q] * rsize;
    c->st->bytes_sent += bytes;
    if (ghost) c->st->bytes_sent_ghost += bytes;
    *rbuf = buf;
    *rtot = rt;
    return GTET_OK;
}

gtet_status mx_exchange(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                        void **rbuf, size_t *rcnt, size_t *rtot, int ghost)
{
    return exchange(c, sbuf, scnt, rsize, rbuf, rcnt, rtot, ghost, 0);
}

gtet_status mx_exchange_keep(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                             void **rbuf, size_t *rcnt, size_t *rtot, int ghost)
{
    return exchange(c, sbuf, scnt, rsize, rbuf, rcnt, rtot, ghost, 1);
}

/* ------------------------------------------------------------------------------------------ */
/* small containers                                                                           */
/* ------------------------------------------------------------------------------------------ */

int mx_hs_grow(hset *h, size_t cap)
{
    uint64_t *k = mx_malloc(cap * sizeof *k);
    if (!k) return -1;
    memset(k, 0xff, cap * sizeof *k);
    for (size_t i = 0; i < h->cap; i++) {
        uint64_t key = h->k[i];
        if (key == NOID) continue;
        size_t j = (size_t)mx_mix64(key) & (cap - 1);
        while (k[j] != NOID) j = (j + 1) & (cap - 1);
        k[j] = key;
    }
    free(h->k);
    h->k = k;
    h->cap = cap;
    return 0;
}

/* 1 inserted, 0 present, -1 out of memory */
int mx_hs_has(const hset *h, uint64_t key)
{
    if (h->cap == 0) return 0;
    size_t j = (size_t)mx_mix64(key) & (h->cap - 1);
    while (h->k[j] != NOID) {
        if (h->k[j] == key) return 1;
        j = (j + 1) & (h->cap - 1);
    }
    return 0;
}

int mx_hs_add(hset *h, uint64_t key)
{
    if (2 * (h->n + 1) > h->cap && mx_hs_grow(h, h->cap ? 2 * h->cap : 64) != 0) return -1;
    size_t j = (size_t)mx_mix64(key) & (h->cap - 1);
    while (h->k[j] != NOID) {
        if (h->k[j] == key) return 0;
        j = (j + 1) & (h->cap - 1);
    }
    h->k[j] = key;
    h->n++;
    return 1;
}

void *mx_vec_push(vec *v)
{
    if (v->n == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 16;
        unsigned char *p = mx_realloc(v->p, cap * v->rs);
        if (!p) return NULL;
        v->p = p;
        v->cap = cap;
    }
    return v->p + v->rs * v->n++;
}

void mx_rank_order(const int *dst, size_t n, int P, size_t *scnt, size_t *pos, size_t *perm)
{
    for (size_t i = 0; i < n; i++) scnt[dst[i]]++;
    pos[0] = 0;
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t i = 0; i < n; i++) perm[pos[dst[i]]++] = i;
}

double mx_box_dist(const double *box, const double *x)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = mx_max(box[k] - x[k], mx_max(0.0, x[k] - box[3 + k]));
        d2 += e * e;
    }
    return sqrt(d2);
}

int mx_env_mode(const char *name)
{
    const char *e = getenv(name);
    if (!e) return 0;
    if (strcmp(e, "off") == 0 || strcmp(e, "0") == 0) return -1;
    if (strcmp(e, "on") == 0 || strcmp(e, "1") == 0) return 1;
    return 0;
}
