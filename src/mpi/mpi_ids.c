/* mpi_ids.c -- steps 1-3 of gtet_triangulate_mpi: the input index ranges and a NaN/Inf
 * anywhere (validation), duplicates across ranks and the global vertex ids (D1 of
 * proofs/distributed.md: mx_step_distinct on the partitioned tiles, mx_step_dedup when some
 * tile holds two equal points), the smallest-id affinely independent simplex of the tiles
 * (dimension). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

/* ------------------------------------------------------------------------------------------ */
/* 1. validation                                                                              */
/* ------------------------------------------------------------------------------------------ */

static int cmp_range(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    return x[0] < y[0] ? -1 : x[0] > y[0];
}

gtet_status mx_step_validate(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    gtet_status s = GTET_OK;
    uint64_t mine[2] = {R->first, (uint64_t)R->n};
    R->firsts_all = mx_malloc(2 * (size_t)P * sizeof(uint64_t));
    uint64_t *sorted = mx_malloc(2 * (size_t)P * sizeof(uint64_t));
    if (!R->firsts_all || !sorted) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(sorted);
        return s;
    }
    MPI_Allgather(mine, 2, MPI_UINT64_T, R->firsts_all, 2, MPI_UINT64_T, c->comm);
    uint64_t *fa = R->firsts_all;
    int nauto = 0;
    for (int q = 0; q < P; q++) nauto += fa[2 * q] == GTET_MPI_AUTO_INDEX;
    if (nauto != 0 && nauto != P) {
        free(sorted);
        return mx_fail(c, GTET_ERR_ARGUMENT, "first_index is GTET_MPI_AUTO_INDEX on %d of %d "
                       "ranks: give it on all of them or on none", nauto, P);
    }
    uint64_t tot = 0;
    for (int q = 0; q < P; q++) {
        if (nauto) fa[2 * q] = tot;
        if (fa[2 * q + 1] > UINT64_MAX / 2 - tot) {
            free(sorted);
            return mx_fail(c, GTET_ERR_TOO_LARGE, "too many points in all");
        }
        tot += fa[2 * q + 1];
    }
    R->N = tot;
    R->first = fa[2 * c->rank];
    /* the nonempty ranges must tile [0, N) */
    int k = 0;
    for (int q = 0; q < P; q++)
        if (fa[2 * q + 1]) {
            sorted[2 * k] = fa[2 * q];
            sorted[2 * k + 1] = fa[2 * q + 1];
            k++;
        }
    mpi_sort(sorted, (size_t)k, 2 * sizeof(uint64_t), cmp_range);
    uint64_t at = 0;
    for (int i = 0; i < k; i++) {
        if (sorted[2 * i] != at) {
            free(sorted);
            return mx_fail(c, GTET_ERR_ARGUMENT, "the ranks' input index ranges do not tile "
                           "[0, %llu): a gap or an overlap at index %llu",
                           (unsigned long long)tot, (unsigned long long)at);
        }
        at += sorted[2 * i + 1];
    }
    free(sorted);
    /* a NaN or Inf anywhere: every rank names the smallest global index */
    uint64_t bad = NOID, gbad = NOID;
    for (size_t i = 0; i < R->n; i++)
        if (!isfinite(R->xyz[3 * i]) || !isfinite(R->xyz[3 * i + 1]) ||
            !isfinite(R->xyz[3 * i + 2])) {
            bad = R->first + i;
            break;
        }
    MPI_Allreduce(&bad, &gbad, 1, MPI_UINT64_T, MPI_MIN, c->comm);
    if (gbad != NOID) {
        c->err.index = (size_t)gbad;
        return mx_fail(c, GTET_ERR_NONFINITE,
                       "input point %llu has a non-finite coordinate (NaN or infinity)",
                       (unsigned long long)gbad);
    }
    if (tot == 0) {
        c->err.dimension = -1;
        return mx_fail(c, GTET_ERR_DEGENERATE_INPUT, "no input points on any rank");
    }
    return GTET_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* 2. duplicates and global vertex ids                                                        */
/* ------------------------------------------------------------------------------------------ */

static int point_lt(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++) {
        if (a[k] < b[k]) return -1;
        if (a[k] > b[k]) return 1;
    }
    return 0;   /* equal, -0.0 == +0.0 */
}

static uint64_t hash_point(const double *x)
{
    uint64_t h = 0x1234567ull;
    for (int k = 0; k < 3; k++) {
        double v = x[k] + 0.0;   /* -0.0 -> +0.0: equal points hash alike */
        uint64_t b;
        memcpy(&b, &v, 8);
        h = mx_mix64(h ^ b);
    }
    return h;
}

static int hash_rank(const double *x, int P)
{
    return (int)(hash_point(x) % (uint64_t)P);
}

/* An open-addressing table of at least 2m slots (a power of two, in *cap), every slot empty
 * (all ones), for first_occurrences and any_duplicate; NULL out of memory. */
static uint64_t *empty_slots(size_t m, size_t *cap)
{
    size_t c = 16;
    while (c < 2 * m) c *= 2;
    uint64_t *slot = mx_malloc(c * sizeof *slot);
    if (slot) memset(slot, 0xff, c * sizeof *slot);
    *cap = c;
    return slot;
}

/* first[k] = the record with the smallest id among those at rb[k]'s coordinates: a hash table
 * of the groups (open addressing on the coordinates' hash, a slot holds the group's
 * smallest-id record), O(m) where sorting the records was this step's largest cost; -1 out of
 * memory.  A slot holds the record's index (m < 2^31: mx_exchange's limit) in its low 32 bits
 * and the hash's high 32 bits above them, so a probe reads a record's coordinates only when
 * the hashes agree (each read of rb is a cache miss on a big tile); empty: all ones (no index
 * is 2^32 - 1) */
static int first_occurrences(const mpt *rb, size_t m, size_t *first)
{
    size_t cap;
    uint64_t *slot = empty_slots(m, &cap);
    if (!slot) return -1;
    const uint64_t lo = 0xffffffffu;
    for (size_t k = 0; k < m; k++) {
        uint64_t h = hash_point(rb[k].x), tag = h & ~lo;
        size_t j = (size_t)h & (cap - 1);
        while (slot[j] != UINT64_MAX &&
               ((slot[j] & ~lo) != tag || point_lt(rb[slot[j] & lo].x, rb[k].x) != 0))
            j = (j + 1) & (cap - 1);
        if (slot[j] == UINT64_MAX || rb[k].id < rb[slot[j] & lo].id) slot[j] = tag | k;
        first[k] = j;
    }
    for (size_t k = 0; k < m; k++) first[k] = (size_t)(slot[first[k]] & lo);
    free(slot);
    return 0;
}

/* 1 when two of rb[0..m) have equal coordinates (compared with ==, as point_lt), 0 when
 * none, -1 out of memory: open addressing on the coordinates' hash, a slot holding the hash's
 * high 32 bits above the record's index (as first_occurrences); the slots of the records
 * DUP_AHEAD on are prefetched (the table is larger than the caches: a probe is a miss) */
#define DUP_AHEAD 16
static int any_duplicate(const mpt *rb, size_t m)
{
    size_t cap;
    uint64_t *slot = empty_slots(m, &cap);
    if (!slot) return -1;
    const uint64_t lo = 0xffffffffu;
    uint64_t ring[DUP_AHEAD];
    for (size_t k = 0; k < m && k < DUP_AHEAD; k++) {
        ring[k] = hash_point(rb[k].x);
        __builtin_prefetch(slot + (ring[k] & (cap - 1)), 1);
    }
    int dup = 0;
    for (size_t k = 0; k < m && !dup; k++) {
        uint64_t h = ring[k % DUP_AHEAD], tag = h & ~lo;
        if (k + DUP_AHEAD < m) {
            uint64_t h2 = hash_point(rb[k + DUP_AHEAD].x);
            ring[k % DUP_AHEAD] = h2;
            __builtin_prefetch(slot + (h2 & (cap - 1)), 1);
        }
        size_t j = (size_t)h & (cap - 1);
        while (slot[j] != UINT64_MAX) {
            if ((slot[j] & ~lo) == tag && point_lt(rb[slot[j] & lo].x, rb[k].x) == 0) {
                dup = 1;
                break;
            }
            j = (j + 1) & (cap - 1);
        }
        slot[j] = tag | k;
    }
    free(slot);
    return dup;
}

/* The duplicate-free path (NOTES.md E201): the partition ran on the caller's points with their
 * input indices, and equal points go to one tile (the kd tree's tests are comparisons, equal
 * coordinates compare alike, -0.0 == +0.0), so "no tile holds two equal points" (an
 * Allreduce(MAX)) is "no duplicate anywhere".  Then every point is its own first occurrence and
 * its vertex id is its input index (D1's numbering with no duplicate), R->tile is already the
 * tile of first occurrences, and the hashing of every point to a rank and its exchange
 * (mx_step_dedup) are not needed.  *dups = 1 when some tile holds two equal points: the caller
 * then runs mx_step_dedup and partitions the first occurrences again. */
gtet_status mx_step_distinct(run *R, int *dups)
{
    mctx *c = &R->c;
    gtet_status s = GTET_OK;
    int dup = R->m > 1 ? any_duplicate(R->tile, R->m) : 0, gdup = 0;
    if (dup < 0) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) return s;
    MPI_Allreduce(&dup, &gdup, 1, MPI_INT, MPI_MAX, c->comm);
    *dups = gdup;
    if (gdup) {
        free(R->tile);
        R->tile = NULL;
        R->m = 0;
        return GTET_OK;
    }
    R->V = R->N;
    R->imap = mx_malloc((R->n + 1) * sizeof *R->imap);
    if (!R->imap) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) return s;
    for (size_t i = 0; i < R->n; i++) R->imap[i] = R->first + i;
    return GTET_OK;
}

gtet_status mx_step_dedup(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    size_t n = R->n;
    gtet_status s = GTET_OK;
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    int *dst = mx_malloc(n * sizeof *dst);
    mpt *sb = mx_malloc(n * sizeof *sb);
    size_t *sidx = mx_malloc(n * sizeof *sidx);
    R->imap = mx_malloc(n * sizeof *R->imap);
    mpt *rb = NULL;
    uint64_t *rep = NULL, *back = NULL;
    size_t *ord = NULL, m = 0;
    if (!scnt || !rcnt || !pos || !dst || !sb || !sidx || !R->imap)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t i = 0; i < n; i++) dst[i] = hash_rank(R->xyz + 3 * i, P);
    mx_rank_order(dst, n, P, scnt, pos, sidx);
    for (size_t k = 0; k < n; k++) {
        memcpy(sb[k].x, R->xyz + 3 * sidx[k], sizeof sb[k].x);
        sb[k].id = R->first + sidx[k];
    }
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(mpt), &r, rcnt, &m, 0)) != GTET_OK) goto done;
        rb = r;
    }
    ord = mx_malloc(m * sizeof *ord);   /* each record's group's first occurrence */
    rep = mx_malloc((m > n ? m : n) * sizeof *rep);
    if (!ord || !rep || first_occurrences(rb, m, ord) != 0)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    /* no duplicate anywhere (the common case): every point is a first occurrence, and the
     * three exchanges that hand out the firsts' ids (24 B a point) are skipped */
    int dup = 0, gdup = 0;
    for (size_t k = 0; k < m; k++) dup |= ord[k] != k;
    MPI_Allreduce(&dup, &gdup, 1, MPI_INT, MPI_MAX, c->comm);
    if (gdup) {
        for (size_t k = 0; k < m; k++) rep[k] = rb[ord[k]].id;
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    /* first occurrences here, numbered after those of the ranks whose ranges come first */
    uint64_t nfirst = gdup ? 0 : (uint64_t)n;
    for (size_t k = 0; k < n && gdup; k++) nfirst += back[k] == sb[k].id;
    uint64_t *cnts = mx_malloc((size_t)P * sizeof *cnts);
    R->fp = mx_malloc((size_t)nfirst * sizeof *R->fp);
    if (!cnts || !R->fp) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(cnts);
        goto done;
    }
    MPI_Allgather(&nfirst, 1, MPI_UINT64_T, cnts, 1, MPI_UINT64_T, c->comm);
    uint64_t base = 0, V = 0;
    for (int q = 0; q < P; q++) {
        V += cnts[q];
        if (R->firsts_all[2 * q + 1] && R->firsts_all[2 * q] < R->first) base += cnts[q];
    }
    free(cnts);
    R->V = V;
    /* vertex ids in input order: imap first holds "is first" marks */
    for (size_t i = 0; i < n; i++) R->imap[i] = NOID;
    for (size_t k = 0; k < n; k++)
        if (!gdup || back[k] == sb[k].id) R->imap[sidx[k]] = 0;
    R->nf = 0;
    for (size_t i = 0; i < n; i++)
        if (R->imap[i] == 0) {
            R->imap[i] = base + R->nf;
            memcpy(R->fp[R->nf].x, R->xyz + 3 * i, sizeof R->fp[0].x);
            R->fp[R->nf].id = R->imap[i];
            R->nf++;
        }
    if (!gdup) goto done;   /* every point is its own first */
    /* second pass: the owners give every record the id of its group's first */
    for (size_t k = 0; k < n; k++) rep[k] = R->imap[sidx[k]];
    free(back);
    back = NULL;
    {
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, scnt, sizeof(uint64_t), &r, rcnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    for (size_t k = 0; k < m; k++) rep[k] = back[ord[k]];
    free(back);
    back = NULL;
    {
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    for (size_t k = 0; k < n; k++) R->imap[sidx[k]] = back[k];
done:
    free(scnt);
    free(rcnt);
    free(pos);
    free(dst);
    free(sb);
    free(sidx);
    free(rb);
    free(ord);
    free(rep);
    free(back);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* 3. dimension                                                                               */
/* ------------------------------------------------------------------------------------------ */

/* exact orient2d of the projections on coordinate plane (i, j), through gtet_orient3d */
static int orient2(const double *a, const double *b, const double *p, int i, int j)
{
    double A[3] = {a[i], a[j], 0}, B[3] = {b[i], b[j], 0}, C[3] = {p[i], p[j], 0};
    static const double up[3] = {0, 0, 1};
    return gtet_orient3d(A, B, C, up);
}

static int seed_ok(const run *R, int stage, const double *x)
{
    switch (stage) {
    case 0: return 1;
    case 1: return point_lt(x, R->seed[0].x) != 0;
    case 2:
        return orient2(R->seed[0].x, R->seed[1].x, x, 0, 1) != 0 ||
               orient2(R->seed[0].x, R->seed[1].x, x, 1, 2) != 0 ||
               orient2(R->seed[0].x, R->seed[1].x, x, 2, 0) != 0;
    default: return gtet_orient3d(R->seed[0].x, R->seed[1].x, R->seed[2].x, x) != 0;
    }
}

/* the DIM_CAND records of t[0..m) with the smallest ids, ascending, into out (all m when fewer);
 * their count.  A stage's smallest-id point passing seed_ok is the first candidate that passes,
 * when one does: every point of a smaller id is a candidate (NOTES.md E228: one scan of the tile
 * instead of one a stage) */
#define DIM_CAND 32
static size_t smallest_ids(const mpt *t, size_t m, mpt *out)
{
    size_t k = 0;
    for (size_t i = 0; i < m; i++) {
        if (k == DIM_CAND && t[i].id >= out[k - 1].id) continue;
        size_t j = k < DIM_CAND ? k++ : k - 1;
        for (; j > 0 && out[j - 1].id > t[i].id; j--) out[j] = out[j - 1];
        out[j] = t[i];
    }
    return k;
}

gtet_status mx_step_dimension(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    mpt *all = mx_malloc((size_t)P * sizeof *all);
    gtet_status s = all ? GTET_OK : mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) return s;
    static const char *what[3] = {"all the same point", "all collinear", "all coplanar"};
    mpt cand[DIM_CAND];
    size_t nc = smallest_ids(R->tile, R->m, cand);
    for (int stage = 0; stage < 4; stage++) {
        mpt best = {{0, 0, 0}, NOID};
        size_t k = 0;
        while (k < nc && !seed_ok(R, stage, cand[k].x)) k++;
        if (k < nc)
            best = cand[k];
        else if (nc < R->m)   /* no candidate passes: the whole tile */
            for (size_t i = 0; i < R->m; i++)
                if (R->tile[i].id < best.id && seed_ok(R, stage, R->tile[i].x)) best = R->tile[i];
        MPI_Allgather(&best, (int)sizeof best, MPI_BYTE, all, (int)sizeof best, MPI_BYTE,
                      c->comm);
        best.id = NOID;
        for (int q = 0; q < P; q++)
            if (all[q].id < best.id) best = all[q];
        if (best.id == NOID) {
            free(all);
            c->err.dimension = stage - 1;
            return mx_fail(c, GTET_ERR_DEGENERATE_INPUT,
                           "degenerate input: the %llu distinct points are %s (affine dimension "
                           "%d); a tetrahedrization needs 4 affinely independent points",
                           (unsigned long long)R->V, what[stage - 1], stage - 1);
        }
        R->seed[stage] = best;
    }
    free(all);
    for (int k = 0; k < 4; k++) R->seed_rank[k] = mx_kd_rank(R, R->seed[k].x);
    return GTET_OK;
}
