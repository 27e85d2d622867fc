/* mpi_triangulate.c -- gtet_triangulate_mpi: the distributed Delaunay tetrahedrization whose
 * union of owned tets is exactly gtet_triangulate's mesh of all the points
 * (proofs/distributed.md has the algorithm's proof; the section names D1..D8 cited below are
 * its lemmas).
 *
 * Steps, each ended by a collective agreement on the status (mx_agree), so that no rank
 * waits in a collective that another rank has left:
 *   1. validate: input index ranges, a NaN/Inf anywhere (smallest global index);
 *   2. duplicates and global vertex ids: points hashed by coordinates to a rank, which finds
 *      each point's first occurrence; ids = first occurrences in global input order (D1);
 *   3. dimension: the smallest-id affinely independent simplex (p0..p3), or an agreed
 *      GTET_ERR_DEGENERATE_INPUT naming the dimension;
 *   4. partition: a kd tree of boxes built by every rank from one gathered sample, one leaf
 *      (tile) per rank; points go to their tile;
 *   5. ghost seeding: each rank sends its points near another tile's bounding box to it;
 *   6. rounds: triangulate tile + ghosts (gtet_triangulate); query, for every tet and hull
 *      facet with a vertex of the tile that is new this round, the ranks whose bounding box
 *      the circumball (hull: the open side of the facet's plane) meets; they answer with
 *      their points in conflict (gtet_insphere_sos / gtet_ghost_conflict, exact) not sent
 *      before; until no rank receives a new point (D3-D5);
 *   7. ownership: a tet belongs to the rank whose tile holds its smallest vertex id; global
 *      tet ids rank by rank; neighbours across ranks by matching facets (D6-D7).
 */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

#define NOID UINT64_MAX

/* ------------------------------------------------------------------------------------------ */
/* small containers                                                                           */
/* ------------------------------------------------------------------------------------------ */

/* open-addressing set of uint64 keys (NOID is the empty slot) */
typedef struct hset {
    uint64_t *k;
    size_t cap, n;
} hset;

static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

static int hs_grow(hset *h, size_t cap)
{
    uint64_t *k = mx_malloc(cap * sizeof *k);
    if (!k) return -1;
    memset(k, 0xff, cap * sizeof *k);
    for (size_t i = 0; i < h->cap; i++) {
        uint64_t key = h->k[i];
        if (key == NOID) continue;
        size_t j = (size_t)mix64(key) & (cap - 1);
        while (k[j] != NOID) j = (j + 1) & (cap - 1);
        k[j] = key;
    }
    free(h->k);
    h->k = k;
    h->cap = cap;
    return 0;
}

/* 1 inserted, 0 present, -1 out of memory */
static int hs_add(hset *h, uint64_t key)
{
    if (2 * (h->n + 1) > h->cap && hs_grow(h, h->cap ? 2 * h->cap : 64) != 0) return -1;
    size_t j = (size_t)mix64(key) & (h->cap - 1);
    while (h->k[j] != NOID) {
        if (h->k[j] == key) return 0;
        j = (j + 1) & (h->cap - 1);
    }
    h->k[j] = key;
    h->n++;
    return 1;
}

/* growable byte vector of fixed-size records */
typedef struct vec {
    unsigned char *p;
    size_t n, cap, rs;
} vec;

static void *vec_push(vec *v)
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

/* ------------------------------------------------------------------------------------------ */
/* run state                                                                                  */
/* ------------------------------------------------------------------------------------------ */

typedef struct grid {
    double lo[3], hi[3], inv[3];
    int g[3];
    int b[3];                   /* blocks of GB^3 cells, for halfspace queries */
    uint32_t *start;            /* cells + 1 */
    uint32_t *idx;              /* tile point indices by cell */
} grid;
#define GB 4

typedef struct run {
    mctx c;
    gtet_options lopt;          /* the local triangulations' options */
    const double *xyz;
    size_t n;
    uint64_t first, N;
    uint64_t *firsts_all;       /* 2 per rank: first index, count */
    uint64_t *imap;
    mpt *fp;                    /* this rank's first occurrences (distinct), id = vertex id */
    size_t nf;
    uint64_t V;
    mpt seed[4];                /* smallest affinely independent simplex */
    int seed_rank[4];           /* the tile each seed lives in */
    /* kd tree */
    struct kdn { int axis, left, right, leaf; double split; } *kd;
    int nkd;
    /* tile and the tiles' boxes */
    mpt *tile;
    size_t m;
    double *box;                /* 6 per rank: lo, hi */
    uint64_t *tcount;           /* per rank */
    /* the local set S: tile points first, then ghosts */
    mpt *sp;
    int *sown;
    size_t ns, scap;
    hset have;                  /* vertex ids in S */
    hset sent;                  /* tile index * P + rank: sent to that rank */
    grid gr;
    gtet_mesh *mesh;
    /* keys of the previous round's queried tets / hull facets, sorted */
    uint64_t (*prev)[4];
    size_t nprev;
} run;

/* ------------------------------------------------------------------------------------------ */
/* 1. validation                                                                              */
/* ------------------------------------------------------------------------------------------ */

static int cmp_range(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    return x[0] < y[0] ? -1 : x[0] > y[0];
}

static gtet_status step_validate(run *R)
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

static const mpt *g_sort_recs;
static int cmp_rec_idx(const void *a, const void *b)
{
    const mpt *x = g_sort_recs + *(const size_t *)a, *y = g_sort_recs + *(const size_t *)b;
    int s = point_lt(x->x, y->x);
    if (s) return s;
    return x->id < y->id ? -1 : x->id > y->id;
}

static int hash_rank(const double *x, int P)
{
    uint64_t h = 0x1234567ull;
    for (int k = 0; k < 3; k++) {
        double v = x[k] + 0.0;   /* -0.0 -> +0.0: equal points hash alike */
        uint64_t b;
        memcpy(&b, &v, 8);
        h = mix64(h ^ b);
    }
    return (int)(h % (uint64_t)P);
}

static gtet_status step_dedup(run *R)
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
    for (size_t i = 0; i < n; i++) {
        dst[i] = hash_rank(R->xyz + 3 * i, P);
        scnt[dst[i]]++;
    }
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t i = 0; i < n; i++) {
        size_t k = pos[dst[i]]++;
        memcpy(sb[k].x, R->xyz + 3 * i, sizeof sb[k].x);
        sb[k].id = R->first + i;
        sidx[k] = i;
    }
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(mpt), &r, rcnt, &m, 0)) != GTET_OK) goto done;
        rb = r;
    }
    ord = mx_malloc(m * sizeof *ord);
    rep = mx_malloc((m > n ? m : n) * sizeof *rep);
    if (!ord || !rep) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < m; k++) ord[k] = k;
    g_sort_recs = rb;
    mpi_sort(ord, m, sizeof *ord, cmp_rec_idx);
    /* each record learns its group's first occurrence */
    for (size_t a = 0; a < m;) {
        size_t b = a + 1;
        while (b < m && point_lt(rb[ord[a]].x, rb[ord[b]].x) == 0) b++;
        for (size_t k = a; k < b; k++) rep[ord[k]] = rb[ord[a]].id;
        a = b;
    }
    {
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    /* first occurrences here, numbered after those of the ranks whose ranges come first */
    uint64_t nfirst = 0;
    for (size_t k = 0; k < n; k++) nfirst += back[k] == sb[k].id;
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
        if (back[k] == sb[k].id) R->imap[sidx[k]] = 0;
    R->nf = 0;
    for (size_t i = 0; i < n; i++)
        if (R->imap[i] == 0) {
            R->imap[i] = base + R->nf;
            memcpy(R->fp[R->nf].x, R->xyz + 3 * i, sizeof R->fp[0].x);
            R->fp[R->nf].id = R->imap[i];
            R->nf++;
        }
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
    for (size_t a = 0; a < m;) {
        size_t b = a + 1;
        while (b < m && point_lt(rb[ord[a]].x, rb[ord[b]].x) == 0) b++;
        uint64_t vid = back[ord[a]];
        for (size_t k = a; k < b; k++) rep[ord[k]] = vid;
        a = b;
    }
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

static gtet_status step_dimension(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    mpt *all = mx_malloc((size_t)P * sizeof *all);
    gtet_status s = all ? GTET_OK : mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) return s;
    static const char *what[3] = {"all the same point", "all collinear", "all coplanar"};
    for (int stage = 0; stage < 4; stage++) {
        mpt best = {{0, 0, 0}, NOID};
        for (size_t i = 0; i < R->nf; i++)
            if (R->fp[i].id < best.id && seed_ok(R, stage, R->fp[i].x)) best = R->fp[i];
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
    return GTET_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* 4. partition: a kd tree of boxes from a gathered sample                                    */
/* ------------------------------------------------------------------------------------------ */

static int g_axis;
static int cmp_axis(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 3; k++) {
        int ax = (g_axis + k) % 3;
        if (x[ax] < y[ax]) return -1;
        if (x[ax] > y[ax]) return 1;
    }
    return 0;
}

static int kd_build(run *R, double *smp, size_t ns, int lo, int hi)
{
    int id = R->nkd++;
    struct kdn *nd = &R->kd[id];
    if (hi - lo == 1) {
        nd->leaf = lo;
        nd->left = nd->right = -1;
        return id;
    }
    nd->leaf = -1;
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < ns; i++)
        for (int k = 0; k < 3; k++) {
            mn[k] = fmin(mn[k], smp[3 * i + k]);
            mx[k] = fmax(mx[k], smp[3 * i + k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (ns && mx[k] - mn[k] > mx[axis] - mn[axis]) axis = k;
    int kl = (hi - lo) / 2;
    g_axis = axis;
    mpi_sort(smp, ns, 3 * sizeof(double), cmp_axis);
    size_t at = (size_t)((double)ns * kl / (hi - lo));
    double split = ns ? smp[3 * (at < ns ? at : ns - 1) + axis] : 0.0;
    size_t j = 0;
    while (j < ns && smp[3 * j + axis] < split) j++;
    nd->axis = axis;
    nd->split = split;
    int l = kd_build(R, smp, j, lo, lo + kl);
    int r = kd_build(R, smp + 3 * j, ns - j, lo + kl, hi);
    R->kd[id].left = l;   /* nd may have moved? no: kd is preallocated */
    R->kd[id].right = r;
    return id;
}

static int kd_rank(const run *R, const double *x)
{
    int id = 0;
    while (R->kd[id].leaf < 0)
        id = x[R->kd[id].axis] < R->kd[id].split ? R->kd[id].left : R->kd[id].right;
    return R->kd[id].leaf;
}

static gtet_status step_partition(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    gtet_status s = GTET_OK;
    size_t S = 2048 * (size_t)P;
    if (S > ((size_t)1 << 20)) S = (size_t)1 << 20;
    size_t mine = R->nf;
    if (R->V > S) mine = (size_t)(((uint64_t)R->nf * S + R->V - 1) / R->V);
    if (mine > R->nf) mine = R->nf;
    int *cnt = mx_malloc(2 * (size_t)P * sizeof *cnt);
    double *my = mx_malloc((3 * mine + 1) * sizeof *my);
    R->kd = mx_malloc(2 * (size_t)P * sizeof *R->kd);
    R->box = mx_malloc(6 * (size_t)P * sizeof *R->box);
    R->tcount = mx_malloc((size_t)P * sizeof *R->tcount);
    double *smp = NULL;
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    int *dst = mx_malloc(R->nf * sizeof *dst);
    mpt *sb = mx_malloc(R->nf * sizeof *sb);
    if (!cnt || !my || !R->kd || !R->box || !R->tcount || !scnt || !rcnt || !pos || !dst || !sb)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < mine; k++) {
        size_t i = (size_t)((double)k * (double)R->nf / (double)mine);
        memcpy(my + 3 * k, R->fp[i].x, 3 * sizeof(double));
    }
    int mi = (int)(3 * mine);
    MPI_Allgather(&mi, 1, MPI_INT, cnt, 1, MPI_INT, c->comm);
    size_t tot = 0;
    for (int q = 0; q < P; q++) {
        cnt[P + q] = (int)tot;
        tot += (size_t)cnt[q];
    }
    smp = mx_malloc((tot + 1) * sizeof *smp);
    if (!smp) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    MPI_Allgatherv(my, mi, MPI_DOUBLE, smp, cnt, cnt + P, MPI_DOUBLE, c->comm);
    R->nkd = 0;
    kd_build(R, smp, tot / 3, 0, P);
    for (size_t i = 0; i < R->nf; i++) {
        dst[i] = kd_rank(R, R->fp[i].x);
        scnt[dst[i]]++;
    }
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t i = 0; i < R->nf; i++) sb[pos[dst[i]]++] = R->fp[i];
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(mpt), &r, rcnt, &R->m, 0)) != GTET_OK)
            goto done;
        R->tile = r;
    }
    for (int k = 0; k < 4; k++) R->seed_rank[k] = kd_rank(R, R->seed[k].x);
    double bb[7] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY, 0};
    for (size_t i = 0; i < R->m; i++)
        for (int k = 0; k < 3; k++) {
            bb[k] = fmin(bb[k], R->tile[i].x[k]);
            bb[3 + k] = fmax(bb[3 + k], R->tile[i].x[k]);
        }
    bb[6] = (double)R->m;
    double *all = mx_malloc(7 * (size_t)P * sizeof *all);
    if (!all) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    MPI_Allgather(bb, 7, MPI_DOUBLE, all, 7, MPI_DOUBLE, c->comm);
    for (int q = 0; q < P; q++) {
        memcpy(R->box + 6 * q, all + 7 * q, 6 * sizeof(double));
        R->tcount[q] = (uint64_t)all[7 * q + 6];
    }
    free(all);
    R->c.st->tile_points = R->m;
done:
    free(cnt);
    free(my);
    free(smp);
    free(scnt);
    free(rcnt);
    free(pos);
    free(dst);
    free(sb);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* geometry: conservative circumballs, boxes, halfspaces (proofs/distributed.md D4)           */
/* ------------------------------------------------------------------------------------------ */

typedef struct ball {
    double c[3], r;   /* every point of the exact closed circumball is within r of c */
    int all;          /* ill-conditioned or out of range: assume it meets everything */
} ball;

static void tet_ball(const double *a, const double *b, const double *cc, const double *d,
                     ball *B)
{
    double ba[3], ca[3], da[3];
    for (int k = 0; k < 3; k++) {
        ba[k] = b[k] - a[k];
        ca[k] = cc[k] - a[k];
        da[k] = d[k] - a[k];
    }
    double lb = ba[0] * ba[0] + ba[1] * ba[1] + ba[2] * ba[2];
    double lc = ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2];
    double ld = da[0] * da[0] + da[1] * da[1] + da[2] * da[2];
    double L = sqrt(fmax(lb, fmax(lc, ld)));
    double x1[3] = {ca[1] * da[2] - ca[2] * da[1], ca[2] * da[0] - ca[0] * da[2],
                    ca[0] * da[1] - ca[1] * da[0]};
    double x2[3] = {da[1] * ba[2] - da[2] * ba[1], da[2] * ba[0] - da[0] * ba[2],
                    da[0] * ba[1] - da[1] * ba[0]};
    double x3[3] = {ba[1] * ca[2] - ba[2] * ca[1], ba[2] * ca[0] - ba[0] * ca[2],
                    ba[0] * ca[1] - ba[1] * ca[0]};
    double D = ba[0] * x1[0] + ba[1] * x1[1] + ba[2] * x1[2];
    B->all = 1;
    if (!(L >= 1e-100 && L <= 1e100) || !(fabs(D) > 0)) return;
    double cond = L * L * L / fabs(D);
    if (!(cond <= 1e12)) return;
    double o[3], amax = 0;
    for (int k = 0; k < 3; k++) {
        o[k] = (lb * x1[k] + lc * x2[k] + ld * x3[k]) / (2 * D);
        B->c[k] = a[k] + o[k];
        amax = fmax(amax, fabs(a[k]));
    }
    double R = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    /* the centre's floating error is below 42 eps cond R (D4); 200 eps cond (R + L) covers it */
    B->r = R * (1 + 1e-6) + 200 * DBL_EPSILON * cond * (R + L) + 1e-14 * (amax + R);
    if (!isfinite(B->r) || !isfinite(B->c[0]) || !isfinite(B->c[1]) || !isfinite(B->c[2]))
        return;
    B->all = 0;
}

static int ball_meets_box(const ball *B, const double *box)
{
    if (B->all) return 1;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = fmax(box[k] - B->c[k], fmax(0.0, B->c[k] - box[3 + k]));
        d2 += e * e;
    }
    return sqrt(d2) <= B->r * (1 + 1e-9);
}

/* exact: does the closed halfspace {orient3d(a,b,c,x) >= 0} meet the box?  (an affine
 * function is largest at a corner) */
static int halfspace_meets_box(const double *a, const double *b, const double *cc,
                               const double *box)
{
    for (int m = 0; m < 8; m++) {
        double x[3] = {box[(m & 1) ? 3 : 0], box[(m & 2) ? 4 : 1], box[(m & 4) ? 5 : 2]};
        if (gtet_orient3d(a, b, cc, x) >= 0) return 1;
    }
    return 0;
}

/* floating filter for the same question, conservative (D4): 1 unless the box is surely on
 * the negative side */
typedef struct hspace {
    double a[3], nrm[3], tol;
    int all;
} hspace;

static void hspace_init(hspace *H, const double *a, const double *b, const double *cc)
{
    double ba[3], ca[3];
    for (int k = 0; k < 3; k++) {
        ba[k] = b[k] - a[k];
        ca[k] = cc[k] - a[k];
        H->a[k] = a[k];
    }
    H->nrm[0] = ba[1] * ca[2] - ba[2] * ca[1];
    H->nrm[1] = ba[2] * ca[0] - ba[0] * ca[2];
    H->nrm[2] = ba[0] * ca[1] - ba[1] * ca[0];
    double lb = sqrt(ba[0] * ba[0] + ba[1] * ba[1] + ba[2] * ba[2]);
    double lc = sqrt(ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2]);
    H->tol = 1e-12 * lb * lc;
    H->all = !(lb >= 1e-100 && lb <= 1e100 && lc >= 1e-100 && lc <= 1e100);
}

static int hspace_meets_box(const hspace *H, const double *lo, const double *hi)
{
    if (H->all) return 1;
    for (int m = 0; m < 8; m++) {
        double x[3] = {((m & 1) ? hi[0] : lo[0]) - H->a[0], ((m & 2) ? hi[1] : lo[1]) - H->a[1],
                       ((m & 4) ? hi[2] : lo[2]) - H->a[2]};
        double v = H->nrm[0] * x[0] + H->nrm[1] * x[1] + H->nrm[2] * x[2];
        double len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (!isfinite(v) || v >= -H->tol * len * 4) return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* the tile's grid (answers queries)                                                          */
/* ------------------------------------------------------------------------------------------ */

static int cell_of(const grid *G, int k, double x)
{
    double t = (x - G->lo[k]) * G->inv[k];
    if (!(t >= 0)) return 0;
    if (t >= G->g[k]) return G->g[k] - 1;
    return (int)t;
}

static gtet_status grid_build(run *R)
{
    grid *G = &R->gr;
    size_t m = R->m;
    if (m == 0) return GTET_OK;
    const double *box = R->box + 6 * R->c.rank;
    double e[3], vol = 1, emax = 0;
    for (int k = 0; k < 3; k++) {
        G->lo[k] = box[k];
        G->hi[k] = box[3 + k];
        e[k] = box[3 + k] - box[k];
        emax = fmax(emax, e[k]);
    }
    for (int k = 0; k < 3; k++) vol *= fmax(e[k], emax * 1e-3);
    double target = fmax(1.0, (double)m / 2);
    double h = cbrt(vol / target);
    size_t cells = 1;
    for (int k = 0; k < 3; k++) {
        double gk = (e[k] > 0 && h > 0 && isfinite(h)) ? floor(e[k] / h) : 1;
        if (!(gk >= 1)) gk = 1;
        if (gk > 1024) gk = 1024;
        G->g[k] = (int)gk;
        G->inv[k] = e[k] > 0 ? G->g[k] / e[k] : 0;
        if (!isfinite(G->inv[k])) G->inv[k] = 0;
        G->b[k] = (G->g[k] + GB - 1) / GB;
        cells *= (size_t)G->g[k];
    }
    G->start = mx_calloc(cells + 1, sizeof *G->start);
    G->idx = mx_malloc(m * sizeof *G->idx);
    uint32_t *cid = mx_malloc(m * sizeof *cid);
    if (!G->start || !G->idx || !cid || m > UINT32_MAX) {
        free(cid);
        return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    }
    for (size_t i = 0; i < m; i++) {
        const double *x = R->tile[i].x;
        size_t ci = ((size_t)cell_of(G, 2, x[2]) * (size_t)G->g[1] + (size_t)cell_of(G, 1, x[1])) *
                        (size_t)G->g[0] + (size_t)cell_of(G, 0, x[0]);
        cid[i] = (uint32_t)ci;
        G->start[ci + 1]++;
    }
    for (size_t ci = 0; ci < cells; ci++) G->start[ci + 1] += G->start[ci];
    for (size_t i = 0; i < m; i++) G->idx[G->start[cid[i]]++] = (uint32_t)i;
    for (size_t ci = cells; ci > 0; ci--) G->start[ci] = G->start[ci - 1];
    G->start[0] = 0;
    free(cid);
    return GTET_OK;
}

/* a conflict query: a tet (4 points, positively oriented) or a hull facet (3 points in
 * ghost order, id[3] == NOID) */
typedef struct query {
    double p[4][3];
    uint64_t id[4];
} query;

/* Answer: append to out (mpt records) the tile points in conflict with q that were not sent
 * to rank `to` before; mark them sent. */
static gtet_status answer(run *R, const query *Q, int to, vec *out)
{
    grid *G = &R->gr;
    size_t m = R->m;
    int P = R->c.size;
    if (m == 0) return GTET_OK;
    int hull = Q->id[3] == NOID;
    ball B;
    hspace H;
    int lo[3] = {0, 0, 0}, hi[3] = {G->g[0] - 1, G->g[1] - 1, G->g[2] - 1};
    if (hull) {
        hspace_init(&H, Q->p[0], Q->p[1], Q->p[2]);
    } else {
        tet_ball(Q->p[0], Q->p[1], Q->p[2], Q->p[3], &B);
        if (!B.all) {
            for (int k = 0; k < 3; k++) {
                double r = B.r * (1 + 1e-9);
                lo[k] = cell_of(G, k, B.c[k] - r);
                hi[k] = cell_of(G, k, B.c[k] + r);
            }
        }
    }
    double cw[3];
    for (int k = 0; k < 3; k++) cw[k] = G->g[k] > 0 && G->inv[k] > 0 ? 1 / G->inv[k] : 0;
    /* halfspace: blocks of GB^3 cells first */
    for (int bz = lo[2] / GB; bz <= hi[2] / GB; bz++)
        for (int by = lo[1] / GB; by <= hi[1] / GB; by++)
            for (int bx = lo[0] / GB; bx <= hi[0] / GB; bx++) {
                int c0[3] = {bx * GB, by * GB, bz * GB};
                if (hull) {
                    double blo[3], bhi[3];
                    for (int k = 0; k < 3; k++) {
                        int c1 = c0[k] + GB;
                        blo[k] = c0[k] == 0 ? G->lo[k] : G->lo[k] + c0[k] * cw[k];
                        bhi[k] = c1 >= G->g[k] ? G->hi[k] : G->lo[k] + c1 * cw[k];
                        /* the cell formula's rounding: widen by a relative hair */
                        double w = 1e-9 * (fabs(blo[k]) + fabs(bhi[k]) + (bhi[k] - blo[k]));
                        blo[k] -= w;
                        bhi[k] += w;
                    }
                    if (!hspace_meets_box(&H, blo, bhi)) continue;
                }
                for (int z = c0[2]; z < c0[2] + GB && z <= hi[2]; z++) {
                    if (z < lo[2]) continue;
                    for (int y = c0[1]; y < c0[1] + GB && y <= hi[1]; y++) {
                        if (y < lo[1]) continue;
                        for (int x = c0[0]; x < c0[0] + GB && x <= hi[0]; x++) {
                            if (x < lo[0]) continue;
                            size_t ci = ((size_t)z * (size_t)G->g[1] + (size_t)y) *
                                            (size_t)G->g[0] + (size_t)x;
                            for (uint32_t j = G->start[ci]; j < G->start[ci + 1]; j++) {
                                const mpt *p = &R->tile[G->idx[j]];
                                if (p->id == Q->id[0] || p->id == Q->id[1] || p->id == Q->id[2] ||
                                    p->id == Q->id[3])
                                    continue;
                                int conflict;
                                if (hull) {
                                    conflict = gtet_ghost_conflict(Q->p[0], Q->p[1], Q->p[2],
                                                                   p->x) > 0;
                                } else {
                                    if (!B.all) {
                                        double d0 = p->x[0] - B.c[0], d1 = p->x[1] - B.c[1],
                                               d2 = p->x[2] - B.c[2];
                                        if (sqrt(d0 * d0 + d1 * d1 + d2 * d2) >
                                            B.r * (1 + 1e-9))
                                            continue;
                                    }
                                    conflict = gtet_insphere_sos(Q->p[0], Q->p[1], Q->p[2],
                                                                 Q->p[3], p->x) > 0;
                                }
                                if (!conflict) continue;
                                int a = hs_add(&R->sent, (uint64_t)G->idx[j] * (uint64_t)P +
                                                             (uint64_t)to);
                                if (a < 0) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY,
                                                          "out of memory");
                                if (a == 0) continue;
                                mpt *o = vec_push(out);
                                if (!o) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY,
                                                       "out of memory");
                                *o = *p;
                            }
                        }
                    }
                }
            }
    return GTET_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* the local set S and its triangulation                                                      */
/* ------------------------------------------------------------------------------------------ */

/* add a point of rank `owner` to S unless present; returns 1 added, 0 present, -1 OOM */
static int s_add(run *R, const mpt *p, int owner)
{
    int a = hs_add(&R->have, p->id);
    if (a <= 0) return a;
    if (R->ns == R->scap) {
        size_t cap = R->scap ? 2 * R->scap : 1024;
        mpt *sp = mx_realloc(R->sp, cap * sizeof *sp);
        if (!sp) return -1;
        R->sp = sp;
        int *so = mx_realloc(R->sown, cap * sizeof *so);
        if (!so) return -1;
        R->sown = so;
        R->scap = cap;
    }
    R->sp[R->ns] = *p;
    R->sown[R->ns] = owner;
    R->ns++;
    return 1;
}

/* add received points (from an exchange with counts rcnt); returns the number new */
static gtet_status s_add_received(run *R, const mpt *rb, const size_t *rcnt, uint64_t *added)
{
    size_t k = 0;
    *added = 0;
    for (int q = 0; q < R->c.size; q++)
        for (size_t i = 0; i < rcnt[q]; i++, k++) {
            int a = s_add(R, &rb[k], q);
            if (a < 0) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
            *added += (uint64_t)a;
        }
    return GTET_OK;
}

static gtet_status triangulate_local(run *R)
{
    gtet_mesh_free(&R->mesh);
    if (R->m == 0) return GTET_OK;
    for (int attempt = 0; attempt < 2; attempt++) {
        double *xyz = mx_malloc(3 * R->ns * sizeof *xyz);
        if (!xyz) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t i = 0; i < R->ns; i++) memcpy(xyz + 3 * i, R->sp[i].x, 3 * sizeof(double));
        gtet_error e;
        memset(&e, 0, sizeof e);
        gtet_options o = R->lopt;
        o.error = &e;
        gtet_status s = gtet_triangulate(xyz, R->ns, &o, &R->mesh);
        free(xyz);
        if (s == GTET_ERR_DEGENERATE_INPUT && attempt == 0) {
            /* the tile with its ghosts is flat or tiny: add the global simplex (D5) */
            for (int k = 0; k < 4; k++)
                if (s_add(R, &R->seed[k], R->seed_rank[k]) < 0)
                    return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
            continue;
        }
        if (s != GTET_OK)
            return mx_fail(&R->c, s, "rank %d: local triangulation of %zu points: %s", R->c.rank,
                           R->ns, e.message);
        size_t nv = gtet_mesh_num_vertices(R->mesh);
        const uint32_t *map = gtet_mesh_input_map(R->mesh);
        if (nv != R->ns)
            return mx_fail(&R->c, GTET_ERR_INTERNAL, "rank %d: distinct points merged locally",
                           R->c.rank);
        for (size_t i = 0; i < R->ns; i++)
            if (map[i] != i)
                return mx_fail(&R->c, GTET_ERR_INTERNAL, "rank %d: local vertex order differs",
                               R->c.rank);
        return GTET_OK;
    }
    return mx_fail(&R->c, GTET_ERR_INTERNAL, "rank %d: degenerate local set with the simplex",
                   R->c.rank);
}

/* ------------------------------------------------------------------------------------------ */
/* 5. ghost seeding, 6. rounds                                                                */
/* ------------------------------------------------------------------------------------------ */

static double box_dist(const double *box, const double *x)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = fmax(box[k] - x[k], fmax(0.0, x[k] - box[3 + k]));
        d2 += e * e;
    }
    return sqrt(d2);
}

static gtet_status exchange_vecs(run *R, vec *out, size_t rs, void **rb, size_t *rcnt,
                                 size_t *rtot)
{
    int P = R->c.size;
    size_t tot = 0;
    for (int q = 0; q < P; q++) tot += out[q].n;
    size_t *scnt = mx_malloc((size_t)P * sizeof *scnt);
    unsigned char *sb = mx_malloc(tot * rs);
    gtet_status s = (scnt && sb) ? GTET_OK : mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY,
                                                     "out of memory");
    if ((s = mx_agree(&R->c, s)) == GTET_OK) {
        size_t at = 0;
        for (int q = 0; q < P; q++) {
            if (out[q].n) memcpy(sb + at * rs, out[q].p, out[q].n * rs);
            at += out[q].n;
            scnt[q] = out[q].n;
        }
        s = mx_exchange(&R->c, sb, scnt, rs, rb, rcnt, rtot, 1);
    }
    free(scnt);
    free(sb);
    for (int q = 0; q < P; q++) {
        free(out[q].p);
        out[q].p = NULL;
        out[q].n = out[q].cap = 0;
    }
    return s;
}

static gtet_status step_seed(run *R, double layer)
{
    int P = R->c.size, me = R->c.rank;
    vec *out = mx_calloc((size_t)P, sizeof *out);
    size_t *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    gtet_status s = (out && rcnt) ? GTET_OK : mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY,
                                                      "out of memory");
    if (s == GTET_OK && R->m) {
        /* room for the tile and a ghost layer up front: no rehashing, fewer page faults */
        size_t want = R->m + R->m / 4 + 64, cap = 64;
        while (cap < 2 * want) cap *= 2;
        mpt *sp = mx_malloc(want * sizeof *sp);
        int *so = mx_malloc(want * sizeof *so);
        if (!sp || !so || hs_grow(&R->have, cap) != 0) {
            free(sp);
            free(so);
            s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        } else {
            R->sp = sp;
            R->sown = so;
            R->scap = want;
        }
    }
    if (s == GTET_OK)
        for (size_t i = 0; i < R->m && s == GTET_OK; i++)
            if (s_add(R, &R->tile[i], me) < 0)
                s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (s == GTET_OK) s = grid_build(R);
    if (s == GTET_OK && R->m) {
        /* the layer: `layer` times the tile's mean spacing */
        const double *bx = R->box + 6 * me;
        double vol = 1, emax = 0;
        for (int k = 0; k < 3; k++) emax = fmax(emax, bx[3 + k] - bx[k]);
        for (int k = 0; k < 3; k++) vol *= fmax(bx[3 + k] - bx[k], emax * 1e-3);
        double delta = layer * cbrt(vol / (double)R->m);
        if (!isfinite(delta)) delta = 0;
        for (int q = 0; q < P; q++) out[q].rs = sizeof(mpt);
        for (size_t i = 0; i < R->m && s == GTET_OK; i++)
            for (int q = 0; q < P; q++) {
                if (q == me || R->tcount[q] == 0) continue;
                if (box_dist(R->box + 6 * q, R->tile[i].x) > delta) continue;
                mpt *o = vec_push(&out[q]);
                if (!o || hs_add(&R->sent, (uint64_t)i * (uint64_t)P + (uint64_t)q) < 0) {
                    s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
                    break;
                }
                *o = R->tile[i];
            }
    }
    if ((s = mx_agree(&R->c, s)) != GTET_OK) {
        if (out)
            for (int q = 0; q < P; q++) free(out[q].p);
        free(out);
        free(rcnt);
        return s;
    }
    void *rb;
    size_t rt;
    s = exchange_vecs(R, out, sizeof(mpt), &rb, rcnt, &rt);
    if (s == GTET_OK) {
        uint64_t added;
        s = s_add_received(R, rb, rcnt, &added);
        R->c.st->ghost_seeded = added;
        free(rb);
    }
    free(out);
    free(rcnt);
    return mx_agree(&R->c, s);
}

static int cmp_key4(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    for (int k = 0; k < 4; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void sort4(uint64_t *k)
{
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            uint64_t t = k[j];
            k[j] = k[j - 1];
            k[j - 1] = t;
        }
}

/* ghost order of the facet opposite f of local tet t: orient3d(a,b,c,apex) < 0 */
static void hull_facet(const run *R, const uint32_t *tv, int f, uint32_t out[3])
{
    int j = 0;
    for (int i = 0; i < 4; i++)
        if (i != f) out[j++] = tv[i];
    if (gtet_orient3d(R->sp[out[0]].x, R->sp[out[1]].x, R->sp[out[2]].x, R->sp[tv[f]].x) > 0) {
        uint32_t t = out[1];
        out[1] = out[2];
        out[2] = t;
    }
}

/* one round's queries: new tets / hull facets with a tile vertex, to every rank whose box
 * they may reach; returns them per rank in out[], and the round's queried keys in R->prev */
static gtet_status make_queries(run *R, vec *out)
{
    int P = R->c.size, me = R->c.rank;
    for (int q = 0; q < P; q++) out[q].rs = sizeof(query);
    if (!R->mesh) {
        free(R->prev);
        R->prev = NULL;
        R->nprev = 0;
        return GTET_OK;
    }
    size_t nt = gtet_mesh_num_tets(R->mesh);
    const uint32_t *tv = gtet_mesh_tets(R->mesh), *nb = gtet_mesh_neighbors(R->mesh);
    vec keys = {NULL, 0, 0, 4 * sizeof(uint64_t)};
    size_t m = R->m;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *v = tv + 4 * t;
        if (v[0] >= m && v[1] >= m && v[2] >= m && v[3] >= m) continue;
        /* the tet */
        for (int pass = 0; pass < 5; pass++) {
            query Q;
            uint64_t key[4];
            if (pass == 0) {
                for (int i = 0; i < 4; i++) {
                    memcpy(Q.p[i], R->sp[v[i]].x, sizeof Q.p[i]);
                    Q.id[i] = key[i] = R->sp[v[i]].id;
                }
            } else {
                int f = pass - 1;
                if (nb[4 * t + f] != GTET_NO_TET) continue;
                uint32_t h[3];
                hull_facet(R, v, f, h);
                if (h[0] >= m && h[1] >= m && h[2] >= m) continue;
                for (int i = 0; i < 3; i++) {
                    memcpy(Q.p[i], R->sp[h[i]].x, sizeof Q.p[i]);
                    Q.id[i] = key[i] = R->sp[h[i]].id;
                }
                memset(Q.p[3], 0, sizeof Q.p[3]);
                Q.id[3] = key[3] = NOID;
            }
            ball B;
            if (pass == 0) tet_ball(Q.p[0], Q.p[1], Q.p[2], Q.p[3], &B);
            int any = 0;
            for (int q = 0; q < P; q++) {
                if (q == me || R->tcount[q] == 0) continue;
                const double *bx = R->box + 6 * q;
                if (pass == 0 ? !ball_meets_box(&B, bx)
                              : !halfspace_meets_box(Q.p[0], Q.p[1], Q.p[2], bx))
                    continue;
                if (!any) {
                    any = 1;
                    sort4(key);
                    uint64_t *kk = vec_push(&keys);
                    if (!kk) goto oom;
                    memcpy(kk, key, sizeof key);
                    /* queried in the previous round and still here: certified (D3) */
                    if (R->prev && bsearch(key, R->prev, R->nprev, sizeof *R->prev, cmp_key4))
                        break;
                }
                query *o = vec_push(&out[q]);
                if (!o) goto oom;
                *o = Q;
                R->c.st->queries_sent++;
            }
        }
    }
    mpi_sort(keys.p, keys.n, keys.rs, cmp_key4);
    free(R->prev);
    R->prev = (uint64_t(*)[4])keys.p;
    R->nprev = keys.n;
    return GTET_OK;
oom:
    free(keys.p);
    return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
}

static gtet_status step_rounds(run *R)
{
    int P = R->c.size;
    gtet_status s = GTET_OK;
    vec *out = mx_calloc((size_t)P, sizeof *out);
    size_t *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    if (!out || !rcnt) s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
    for (int round = 1;; round++) {
        double t0 = mx_now();
        s = triangulate_local(R);
        R->c.st->rounds = round;
        R->c.st->seconds_triangulate += mx_now() - t0;
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        t0 = mx_now();
        s = make_queries(R, out);
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        void *rb;
        size_t rt;
        if ((s = exchange_vecs(R, out, sizeof(query), &rb, rcnt, &rt)) != GTET_OK) goto done;
        /* answer every query with this tile's conflicting points not sent before */
        const query *qs = rb;
        for (int q = 0; q < P; q++) out[q].rs = sizeof(mpt);
        size_t k = 0;
        for (int q = 0; q < P && s == GTET_OK; q++)
            for (size_t i = 0; i < rcnt[q] && s == GTET_OK; i++, k++)
                s = answer(R, &qs[k], q, &out[q]);
        free(rb);
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        if ((s = exchange_vecs(R, out, sizeof(mpt), &rb, rcnt, &rt)) != GTET_OK) goto done;
        uint64_t added = 0, gadded = 0;
        s = s_add_received(R, rb, rcnt, &added);
        free(rb);
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        MPI_Allreduce(&added, &gadded, 1, MPI_UINT64_T, MPI_SUM, R->c.comm);
        R->c.st->seconds_exchange += mx_now() - t0;
        if (gadded == 0) break;   /* every queried tet is certified: S is final (D3) */
    }
done:
    if (out)
        for (int q = 0; q < P; q++) free(out[q].p);
    free(out);
    free(rcnt);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* 7. ownership, global ids, neighbours                                                       */
/* ------------------------------------------------------------------------------------------ */

typedef struct frec {
    uint64_t key[3];
    uint64_t tet;    /* global id */
} frec;

static const frec *g_frecs;
static int cmp_frec_idx(const void *a, const void *b)
{
    const frec *x = g_frecs + *(const size_t *)a, *y = g_frecs + *(const size_t *)b;
    for (int k = 0; k < 3; k++)
        if (x->key[k] != y->key[k]) return x->key[k] < y->key[k] ? -1 : 1;
    return x->tet < y->tet ? -1 : x->tet > y->tet;
}

static int cmp_mpt_id(const void *a, const void *b)
{
    uint64_t x = ((const mpt *)a)->id, y = ((const mpt *)b)->id;
    return x < y ? -1 : x > y;
}

static gtet_status step_output(run *R, gtet_mpi_result *res)
{
    mctx *c = &R->c;
    int P = c->size, me = c->rank;
    gtet_status s = GTET_OK;
    size_t nt = R->mesh ? gtet_mesh_num_tets(R->mesh) : 0;
    const uint32_t *tv = R->mesh ? gtet_mesh_tets(R->mesh) : NULL;
    const uint32_t *nb = R->mesh ? gtet_mesh_neighbors(R->mesh) : NULL;
    size_t m = R->m;
    uint64_t *gid = mx_malloc(nt * sizeof *gid);
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    vec fr = {NULL, 0, 0, sizeof(frec)};
    vec slot = {NULL, 0, 0, sizeof(uint64_t)};
    frec *sb = NULL, *rb = NULL;
    size_t *ord = NULL, *perm = NULL;
    uint64_t *rep = NULL, *back = NULL;
    res->tet_offsets = mx_malloc(((size_t)P + 1) * sizeof *res->tet_offsets);
    if (!gid || !scnt || !rcnt || !pos || !res->tet_offsets)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    size_t own = 0;
    if (s == GTET_OK)
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *v = tv + 4 * t;
            uint32_t lo = v[0];
            for (int i = 1; i < 4; i++)
                if (R->sp[v[i]].id < R->sp[lo].id) lo = v[i];
            gid[t] = lo < m ? own++ : NOID;   /* the smallest vertex is in this tile (D6) */
        }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    uint64_t mine = own;
    MPI_Allgather(&mine, 1, MPI_UINT64_T, res->tet_offsets + 1, 1, MPI_UINT64_T, c->comm);
    res->tet_offsets[0] = 0;
    for (int q = 0; q < P; q++) res->tet_offsets[q + 1] += res->tet_offsets[q];
    res->tet_offset = res->tet_offsets[me];
    res->num_tets_global = res->tet_offsets[P];
    res->num_tets = own;
    for (size_t t = 0; t < nt; t++)
        if (gid[t] != NOID) gid[t] += res->tet_offset;
    res->tets = mx_malloc(4 * own * sizeof *res->tets);
    res->neighbors = mx_malloc(4 * own * sizeof *res->neighbors);
    if (!res->tets || !res->neighbors) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t t = 0; t < nt && s == GTET_OK; t++) {
        if (gid[t] == NOID) continue;
        size_t o = (size_t)(gid[t] - res->tet_offset);
        const uint32_t *v = tv + 4 * t;
        for (int f = 0; f < 4; f++) {
            res->tets[4 * o + f] = R->sp[v[f]].id;
            uint32_t u = nb[4 * t + f];
            int tilev = 0;
            for (int i = 0; i < 4; i++)
                if (i != f && v[i] < m) tilev = 1;
            if (u != GTET_NO_TET && gid[u] != NOID) {
                res->neighbors[4 * o + f] = gid[u];   /* both owned here: both final (D7) */
            } else if (u == GTET_NO_TET && tilev) {
                res->neighbors[4 * o + f] = GTET_MPI_NO_TET;  /* certified hull facet */
            } else {
                frec *r = vec_push(&fr);
                uint64_t *sl = vec_push(&slot);
                if (!r || !sl) {
                    s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
                    break;
                }
                uint64_t k4[4] = {0, 0, 0, 0};
                int j = 1;
                for (int i = 0; i < 4; i++)
                    if (i != f) k4[j++] = R->sp[v[i]].id;
                sort4(k4);
                memcpy(r->key, k4 + 1, sizeof r->key);
                r->tet = gid[t];
                *sl = 4 * o + (size_t)f;
                res->neighbors[4 * o + f] = GTET_MPI_NO_TET;
            }
        }
    }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    /* facet matching: records hashed by their key (D7) */
    size_t nr = fr.n;
    const frec *frs = (const frec *)fr.p;
    int *dst = mx_malloc(nr * sizeof *dst);
    sb = mx_malloc(nr * sizeof *sb);
    perm = mx_malloc(nr * sizeof *perm);
    if (!dst || !sb || !perm) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(dst);
        goto done;
    }
    for (size_t i = 0; i < nr; i++) {
        dst[i] = (int)(mix64(frs[i].key[0] ^ mix64(frs[i].key[1] ^ mix64(frs[i].key[2]))) %
                       (uint64_t)P);
        scnt[dst[i]]++;
    }
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t i = 0; i < nr; i++) {
        size_t k = pos[dst[i]]++;
        sb[k] = frs[i];
        perm[k] = i;
    }
    free(dst);
    size_t mr;
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(frec), &r, rcnt, &mr, 0)) != GTET_OK) goto done;
        rb = r;
    }
    ord = mx_malloc(mr * sizeof *ord);
    rep = mx_malloc(mr * sizeof *rep);
    if (!ord || !rep) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < mr; k++) ord[k] = k;
    g_frecs = rb;
    mpi_sort(ord, mr, sizeof *ord, cmp_frec_idx);
    for (size_t a = 0; a < mr && s == GTET_OK;) {
        size_t b = a + 1;
        while (b < mr && !memcmp(rb[ord[a]].key, rb[ord[b]].key, sizeof rb[0].key)) b++;
        if (b - a == 1) {
            rep[ord[a]] = GTET_MPI_NO_TET;   /* one side only: a hull facet */
        } else if (b - a == 2) {
            rep[ord[a]] = rb[ord[a + 1]].tet;
            rep[ord[a + 1]] = rb[ord[a]].tet;
        } else {
            s = mx_fail(c, GTET_ERR_INTERNAL, "facet (%llu, %llu, %llu) is in %zu owned tets",
                        (unsigned long long)rb[ord[a]].key[0],
                        (unsigned long long)rb[ord[a]].key[1],
                        (unsigned long long)rb[ord[a]].key[2], b - a);
        }
        a = b;
    }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    {
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    const uint64_t *sls = (const uint64_t *)slot.p;
    uint64_t hull = 0, ghull = 0;
    for (size_t k = 0; k < nr; k++) res->neighbors[sls[perm[k]]] = back[k];
    for (size_t i = 0; i < 4 * own; i++) hull += res->neighbors[i] == GTET_MPI_NO_TET;
    MPI_Allreduce(&hull, &ghull, 1, MPI_UINT64_T, MPI_SUM, c->comm);
    res->num_hull_facets = ghull;
    /* the tile's vertices and the vertices the owned tets use */
    res->num_tile_vertices = m;
    res->tile_vertex_ids = mx_malloc(m * sizeof *res->tile_vertex_ids);
    res->tile_vertices = mx_malloc(3 * m * sizeof *res->tile_vertices);
    uint64_t *used = mx_malloc((R->ns + 1) * sizeof *used);
    if (!res->tile_vertex_ids || !res->tile_vertices || !used) {
        free(used);
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t i = 0; i < m; i++) {
        res->tile_vertex_ids[i] = R->tile[i].id;
        memcpy(res->tile_vertices + 3 * i, R->tile[i].x, 3 * sizeof(double));
    }
    /* the used vertices: marked over S, listed by vertex id */
    uint32_t *slotof = mx_malloc((R->ns + 1) * sizeof *slotof);
    mpt *lst = mx_malloc((R->ns + 1) * sizeof *lst);
    if (!slotof || !lst) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(slotof);
        free(lst);
        free(used);
        goto done;
    }
    memset(slotof, 0, (R->ns + 1) * sizeof *slotof);
    for (size_t t = 0; t < nt; t++)
        if (gid[t] != NOID)
            for (int i = 0; i < 4; i++) slotof[tv[4 * t + i]] = 1;
    size_t w = 0;
    for (size_t i = 0; i < R->ns; i++)
        if (slotof[i]) {
            lst[w] = R->sp[i];
            lst[w].id = R->sp[i].id;
            w++;
        }
    mpi_sort(lst, w, sizeof *lst, cmp_mpt_id);
    res->num_used_vertices = w;
    res->used_vertex_ids = used;
    res->used_vertices = mx_malloc((3 * w + 1) * sizeof *res->used_vertices);
    if (!res->used_vertices) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (s == GTET_OK)
        for (size_t i = 0; i < w; i++) {
            used[i] = lst[i].id;
            memcpy(res->used_vertices + 3 * i, lst[i].x, 3 * sizeof(double));
        }
    free(slotof);
    free(lst);
    s = mx_agree(c, s);
done:
    free(gid);
    free(scnt);
    free(rcnt);
    free(pos);
    free(fr.p);
    free(slot.p);
    free(sb);
    free(rb);
    free(ord);
    free(perm);
    free(rep);
    free(back);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* entry point                                                                                */
/* ------------------------------------------------------------------------------------------ */

void gtet_mpi_result_free(gtet_mpi_result *r)
{
    if (!r) return;
    free(r->input_map);
    free(r->tets);
    free(r->neighbors);
    free(r->tet_offsets);
    free(r->tile_vertex_ids);
    free(r->tile_vertices);
    free(r->used_vertex_ids);
    free(r->used_vertices);
    memset(r, 0, sizeof *r);
}

static void run_free(run *R)
{
    free(R->firsts_all);
    free(R->imap);
    free(R->fp);
    free(R->kd);
    free(R->tile);
    free(R->box);
    free(R->tcount);
    free(R->sp);
    free(R->sown);
    free(R->have.k);
    free(R->sent.k);
    free(R->gr.start);
    free(R->gr.idx);
    free(R->prev);
    gtet_mesh_free(&R->mesh);
    free(R->c.sc);
}

/* the layer of ghost points sent before the first triangulation, in tile spacings */
#ifndef GTET_MPI_LAYER
#define GTET_MPI_LAYER 2.5
#endif

gtet_status gtet_triangulate_mpi(MPI_Comm comm, const double *xyz, size_t n,
                                 uint64_t first_index, const gtet_options *opts,
                                 gtet_mpi_result *result)
{
    double t0 = mx_now();
    run R;
    memset(&R, 0, sizeof R);
    gtet_mpi_result res;
    memset(&res, 0, sizeof res);
    R.c.comm = comm;
    MPI_Comm_rank(comm, &R.c.rank);
    MPI_Comm_size(comm, &R.c.size);
    R.c.st = &res.stats;
    R.c.err.index = SIZE_MAX;
    R.c.err.dimension = -1;
    res.stats.ranks = R.c.size;
    gtet_options_init(&R.lopt);
    if (opts) R.lopt = *opts;
    R.lopt.check = 0;
    R.lopt.progress = NULL;
    R.lopt.degeneracies = 0;
    R.lopt.error = NULL;
    R.xyz = xyz;
    R.n = n;
    R.first = first_index;
    gtet_status s = GTET_OK;
    if (!result || (!xyz && n > 0) || (opts && opts->threads < 0))
        s = mx_fail(&R.c, GTET_ERR_ARGUMENT, "rank %d: %s", R.c.rank,
                    !result ? "result is NULL" : !xyz && n ? "xyz is NULL with n > 0"
                                                           : "threads < 0");
    R.c.sc = mx_malloc(4 * (size_t)R.c.size * sizeof(int));
    if (!R.c.sc && s == GTET_OK) s = mx_fail(&R.c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (R.c.sc) {
        R.c.sd = R.c.sc + R.c.size;
        R.c.rc = R.c.sd + R.c.size;
        R.c.rd = R.c.rc + R.c.size;
    }
    if ((s = mx_agree(&R.c, s)) != GTET_OK) goto fail;
    double t = mx_now();
    if ((s = mx_agree(&R.c, step_validate(&R))) != GTET_OK) goto fail;
    if ((s = step_dedup(&R)) != GTET_OK) goto fail;
    if ((s = mx_agree(&R.c, step_dimension(&R))) != GTET_OK) goto fail;
    res.stats.seconds_validate = mx_now() - t;
    t = mx_now();
    if ((s = mx_agree(&R.c, step_partition(&R))) != GTET_OK) goto fail;
    res.stats.seconds_partition = mx_now() - t;
    t = mx_now();
    if ((s = step_seed(&R, GTET_MPI_LAYER)) != GTET_OK) goto fail;
    res.stats.seconds_exchange = mx_now() - t;
    if ((s = step_rounds(&R)) != GTET_OK) goto fail;
    res.stats.ghost_points = R.ns - R.m;
    if (opts && opts->check && R.mesh) {
        /* the exact checker on this rank's local triangulation */
        double *pts = mx_malloc(3 * R.ns * sizeof *pts);
        if (!pts) {
            s = mx_fail(&R.c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        } else {
            for (size_t i = 0; i < R.ns; i++) memcpy(pts + 3 * i, R.sp[i].x, 3 * sizeof(double));
            gtet_check_report rep;
            s = gtet_check(R.mesh, pts, R.ns, 0, &rep);
            free(pts);
            if (s != GTET_OK)
                mx_fail(&R.c, s, "rank %d: local check: %s", R.c.rank, rep.message);
        }
    }
    if ((s = mx_agree(&R.c, s)) != GTET_OK) goto fail;
    t = mx_now();
    if ((s = step_output(&R, &res)) != GTET_OK) goto fail;
    res.stats.seconds_output = mx_now() - t;
    res.num_points_global = R.N;
    res.num_vertices = R.V;
    res.num_duplicates = R.N - R.V;
    res.num_points = n;
    res.input_map = R.imap;
    R.imap = NULL;
    if (opts && opts->check) {
        gtet_check_report rep;
        s = gtet_check_mpi(comm, &res, &rep);
        if (s != GTET_OK) {
            mx_fail(&R.c, s, "%s", rep.message);
            goto fail;
        }
    }
    run_free(&R);
    res.stats.seconds_total = mx_now() - t0;
    *result = res;
    return GTET_OK;
fail:
    if (opts && opts->error) *opts->error = R.c.err;
    run_free(&R);
    gtet_mpi_result_free(&res);
    if (result) memset(result, 0, sizeof *result);
    return s;
}
