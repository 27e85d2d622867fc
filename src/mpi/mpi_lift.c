/* mpi_lift.c -- a round's circumball answers from a triangulation of the tile and the queries'
 * vertices (proofs/distributed.md D12).
 *
 * Where every circumball holds most of the tile (points on a sphere, co-spherical sets), the
 * grid scan of mx_answer tests nearly every tile point against every query: quadratic.  Then,
 * once per round, the answering rank triangulates X = its tile (S's first m points) and every
 * vertex of the circumball queries it received; by D12 the tile points in conflict with a
 * query's tet are the vertices a search from one of the tet's vertices reaches through
 * vertices in conflict in DT(X), so an answer costs the tests of the conflicting points and
 * their neighbours only.  Which way a round answers is decided from the points the scans
 * would visit (mx_lift_build's gate): the answers are the same sets either way, until a
 * round's searches for one asker go over LIFT_DUMP_LIMIT (then its answers are complete:
 * the rest of the tile). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "mpi/mpi_internal.h"

/* The scans of one round may visit up to LIFT_SCAN_LIMIT times the tile's points before the
 * round triangulates X instead (a scanned point costs tens of nanoseconds, an inserted one
 * about a microsecond): either way a round's answers cost O(m) plus what they send, or
 * O(|X| log |X|). */
#ifndef LIFT_SCAN_LIMIT
#define LIFT_SCAN_LIMIT 32
#endif

/* A round's searches for one asking rank may make up to LIFT_DUMP_LIMIT exact tests per tile
 * point; past that, the rest of the tile not sent to it yet is its answer (D12: a complete
 * answer).  Where the tets' conflict sets are large (surface samples, whose ghosts are most of
 * the other tiles) the searches would go over the same points query after query. */
#ifndef LIFT_DUMP_LIMIT
#define LIFT_DUMP_LIMIT 16
#endif

/* the summed-area table of the grid's cell counts: sat[((z * (g1 + 1)) + y) * (g0 + 1) + x]
 * counts the points of the cells below (x, y, z) on every axis; built once a run */
static gtet_status grid_sat(run *R)
{
    grid *G = &R->gr;
    if (G->sat) return GTET_OK;
    size_t a = (size_t)G->g[0] + 1, b = (size_t)G->g[1] + 1, c = (size_t)G->g[2] + 1;
    G->sat = mx_calloc(a * b * c, sizeof *G->sat);
    if (!G->sat) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    size_t ci = 0;
    for (size_t z = 1; z < c; z++)
        for (size_t y = 1; y < b; y++)
            for (size_t x = 1; x < a; x++, ci++) {
                uint32_t n = G->start[ci + 1] - G->start[ci];
                G->sat[(z * b + y) * a + x] = n + G->sat[(z * b + y) * a + x - 1] +
                                              G->sat[(z * b + y - 1) * a + x] +
                                              G->sat[((z - 1) * b + y) * a + x] -
                                              G->sat[(z * b + y - 1) * a + x - 1] -
                                              G->sat[((z - 1) * b + y) * a + x - 1] -
                                              G->sat[((z - 1) * b + y - 1) * a + x] +
                                              G->sat[((z - 1) * b + y - 1) * a + x - 1];
            }
    return GTET_OK;
}

/* the tile points in the cells lo..hi (inclusive) */
static uint64_t grid_count(const grid *G, const int lo[3], const int hi[3])
{
    size_t a = (size_t)G->g[0] + 1, b = (size_t)G->g[1] + 1;
#define S_(x, y, z) ((int64_t)G->sat[((size_t)(z) * b + (size_t)(y)) * a + (size_t)(x)])
    int64_t x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = hi[0] + 1, y1 = hi[1] + 1, z1 = hi[2] + 1;
    int64_t v = S_(x1, y1, z1) - S_(x0, y1, z1) - S_(x1, y0, z1) - S_(x1, y1, z0) +
                S_(x0, y0, z1) + S_(x0, y1, z0) + S_(x1, y0, z0) - S_(x0, y0, z0);
#undef S_
    return v > 0 ? (uint64_t)v : 0;
}

/* vertex id -> X index (open addressing, NOID the empty key; mcap a power of two over twice
 * the entries) */
static size_t map_slot(const lift *L, uint64_t id)
{
    size_t mask = L->mcap - 1, h = (size_t)mx_mix64(id) & mask;
    while (L->mk[h] != NOID && L->mk[h] != id) h = (h + 1) & mask;
    return h;
}

static int map_find(const lift *L, uint64_t id, uint32_t *ix)
{
    size_t h = map_slot(L, id);
    if (L->mk[h] != id) return 0;
    *ix = L->mv[h];
    return 1;
}

void mx_lift_free(lift *L)
{
    free(L->adj0);
    free(L->adj);
    free(L->mk);
    free(L->mv);
    free(L->stamp);
    free(L->queue);
    free(L->xp);
    free(L->tets);
    free(L->work);
    memset(L, 0, sizeof *L);
}

static const double *lift_point(const run *R, const lift *L, uint32_t i)
{
    return i < R->m ? R->sp[i].x : L->xp[i - R->m].x;
}

/* X: the tile as indices 0..m-1, then the ball queries' vertices that are not tile points,
 * each once (by vertex id: distinct ids are distinct points, D1) */
static gtet_status lift_collect(run *R, lift *L, const query *qs, size_t nq, size_t nball)
{
    size_t m = R->m, want = 2 * (m + 4 * nball) + 16;
    L->mcap = 16;
    while (L->mcap < want) L->mcap *= 2;
    L->mk = mx_malloc(L->mcap * sizeof *L->mk);
    L->mv = mx_malloc(L->mcap * sizeof *L->mv);
    L->xp = mx_malloc((4 * nball + 1) * sizeof *L->xp);
    if (!L->mk || !L->mv || !L->xp || m + 4 * nball >= UINT32_MAX)
        return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (answers' triangulation)");
    memset(L->mk, 0xff, L->mcap * sizeof *L->mk);
    for (size_t i = 0; i < m; i++) {
        size_t h = map_slot(L, R->sp[i].id);
        L->mk[h] = R->sp[i].id;
        L->mv[h] = (uint32_t)i;
    }
    size_t nx = m;
    for (size_t k = 0; k < nq; k++) {
        if (qs[k].id[3] == NOID) continue;
        for (int i = 0; i < 4; i++) {
            size_t h = map_slot(L, qs[k].id[i]);
            if (L->mk[h] == qs[k].id[i]) continue;
            L->mk[h] = qs[k].id[i];
            L->mv[h] = (uint32_t)nx;
            mpt *o = &L->xp[nx - m];
            memcpy(o->x, qs[k].p[i], sizeof o->x);
            o->id = qs[k].id[i];
            nx++;
        }
    }
    L->nx = nx;
    return GTET_OK;
}

/* DT(X) and its vertex adjacency (adj0/adj: each vertex's neighbours, each once) */
static gtet_status lift_adjacency(run *R, lift *L, const gtet_mesh *M)
{
    size_t nx = L->nx, nt = gtet_mesh_num_tets(M);
    const uint32_t *tv = gtet_mesh_tets(M);
    L->adj0 = mx_calloc(nx + 1, sizeof *L->adj0);
    L->adj = mx_malloc((12 * nt + 1) * sizeof *L->adj);
    L->stamp = mx_calloc(nx + 1, sizeof *L->stamp);
    if (!L->adj0 || !L->adj || !L->stamp)
        return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (answers' triangulation)");
    for (size_t t = 0; t < 4 * nt; t++) L->adj0[tv[t] + 1] += 3;
    for (size_t i = 0; i < nx; i++) L->adj0[i + 1] += L->adj0[i];
    size_t *at = mx_malloc((nx + 1) * sizeof *at);
    if (!at) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (answers' triangulation)");
    memcpy(at, L->adj0, (nx + 1) * sizeof *at);
    for (size_t t = 0; t < nt; t++)
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                if (j != i) L->adj[at[tv[4 * t + i]]++] = tv[4 * t + j];
    /* each vertex's list without repeats (an edge is in several tets), compacted in place */
    size_t w = 0;
    for (size_t i = 0; i < nx; i++) {
        size_t b = L->adj0[i], e = at[i];
        L->adj0[i] = w;
        for (size_t k = b; k < e; k++) {
            uint32_t u = L->adj[k];
            if (L->stamp[u] == (uint32_t)i + 1) continue;
            L->stamp[u] = (uint32_t)i + 1;
            L->adj[w++] = u;
        }
    }
    L->adj0[nx] = w;
    free(at);
    memset(L->stamp, 0, (nx + 1) * sizeof *L->stamp);
    L->cur = 0;
    return GTET_OK;
}

static void sort4u(uint32_t *k)
{
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            uint32_t t = k[j];
            k[j] = k[j - 1];
            k[j - 1] = t;
        }
}

static size_t tet_hash(const uint32_t *k, size_t mask)
{
    uint64_t a = ((uint64_t)k[0] << 32 | k[1]), b = ((uint64_t)k[2] << 32 | k[3]);
    return (size_t)mx_mix64(a ^ mx_mix64(b)) & mask;
}

/* is the tet with X indices k (ascending) a tet of DT(X)? */
static int tet_in(const lift *L, const uint32_t *k)
{
    size_t mask = L->tcap - 1;
    for (size_t h = tet_hash(k, mask);; h = (h + 1) & mask) {
        const uint32_t *e = L->tets[h];
        if (e[0] == UINT32_MAX) return 0;
        if (e[0] == k[0] && e[1] == k[1] && e[2] == k[2] && e[3] == k[3]) return 1;
    }
}

/* L->tets: DT(X)'s tets by their sorted X indices */
static gtet_status lift_tets(run *R, lift *L, const gtet_mesh *M)
{
    size_t nt = gtet_mesh_num_tets(M);
    const uint32_t *tv = gtet_mesh_tets(M);
    L->tcap = 16;
    while (L->tcap < nt + nt / 2 + 16) L->tcap *= 2;
    L->tets = mx_malloc(L->tcap * sizeof *L->tets);
    if (!L->tets) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (answers' triangulation)");
    memset(L->tets, 0xff, L->tcap * sizeof *L->tets);
    size_t mask = L->tcap - 1;
    for (size_t t = 0; t < nt; t++) {
        uint32_t k[4] = {tv[4 * t], tv[4 * t + 1], tv[4 * t + 2], tv[4 * t + 3]};
        sort4u(k);
        size_t h = tet_hash(k, mask);
        while (L->tets[h][0] != UINT32_MAX) h = (h + 1) & mask;
        memcpy(L->tets[h], k, sizeof k);
    }
    return GTET_OK;
}

/* DT(X) by the kernel (X is distinct: D1); *ok = 0 when X is not 3-dimensional (then the
 * round scans) */
static gtet_status lift_triangulate(run *R, lift *L, int *ok)
{
    size_t nx = L->nx;
    *ok = 0;
    double *xyz = mx_malloc(3 * nx * sizeof *xyz);
    if (!xyz) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (answers' triangulation)");
    for (uint32_t i = 0; i < nx; i++) memcpy(xyz + 3 * i, lift_point(R, L, i), 3 * sizeof(double));
    gtet_error e;
    gtet_mesh *M = NULL;
    gtet_status s = mx_triangulate_own(&R->lopt, xyz, nx, &M, &e);
    if (s == GTET_ERR_DEGENERATE_INPUT) return GTET_OK;
    if (s != GTET_OK)
        return mx_fail(&R->c, s, "rank %d: the answers' triangulation of %zu points: %s",
                       R->c.rank, nx, e.message);
    if (gtet_mesh_num_vertices(M) != nx) {
        gtet_mesh_free(&M);
        return mx_fail(&R->c, GTET_ERR_INTERNAL, "rank %d: distinct points merged (answers)",
                       R->c.rank);
    }
    s = lift_adjacency(R, L, M);
    if (s == GTET_OK) s = lift_tets(R, L, M);
    gtet_mesh_free(&M);
    *ok = s == GTET_OK;
    return s;
}

/* does L hold every vertex of the tet queries?  (then the lemma of D12 applies to them with
 * the same X: it asks only X ⊇ the tile and the tet's vertices) */
static int lift_holds(const lift *L, const query *qs, size_t nq)
{
    for (size_t k = 0; k < nq; k++) {
        if (qs[k].id[3] == NOID) continue;
        for (int i = 0; i < 4; i++) {
            uint32_t ix;
            if (!map_find(L, qs[k].id[i], &ix)) return 0;
        }
    }
    return 1;
}

gtet_status mx_lift_build(run *R, const query *qs, size_t nq, lift *L)
{
    size_t m = R->m, nball = 0;
    if (L->on && lift_holds(L, qs, nq)) {
        memset(L->work, 0, (size_t)R->c.size * sizeof *L->work);
        return GTET_OK;
    }
    mx_lift_free(L);
    if (m == 0 || nq == 0) return GTET_OK;
    gtet_status s = grid_sat(R);
    if (s != GTET_OK) return s;
    /* the gate: the points the scans would visit at most (the cells of each ball's clipped
     * range, mx_ball_range) against LIFT_SCAN_LIMIT m */
    uint64_t visit = 0, limit = (uint64_t)LIFT_SCAN_LIMIT * (uint64_t)m;
    for (size_t k = 0; k < nq; k++) {
        if (qs[k].id[3] == NOID) continue;
        nball++;
        if (visit > limit) continue;   /* decided: only nball is still counted */
        ball B;
        int lo[3], hi[3];
        mx_tet_ball(qs[k].p[0], qs[k].p[1], qs[k].p[2], qs[k].p[3], &B);
        mx_ball_range(&R->gr, &B, lo, hi);
        visit += grid_count(&R->gr, lo, hi);
    }
    /* GTET_MPI_LIFT=off: always the scans; =on: always DT(X) (the tests compare the three) */
    int mode = mx_env_mode("GTET_MPI_LIFT");
    if (mode < 0 || (mode == 0 && visit <= limit)) return GTET_OK;
    int ok = 0;
    L->work = mx_calloc((size_t)R->c.size, sizeof *L->work);
    if (!L->work) s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (s == GTET_OK && (s = lift_collect(R, L, qs, nq, nball)) == GTET_OK)
        s = lift_triangulate(R, L, &ok);
    if (s != GTET_OK || !ok) {
        mx_lift_free(L);
        return s;
    }
    L->on = 1;
    R->c.st->answer_lifts++;
    return GTET_OK;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* The tile points in conflict with the tet query Q, not sent to `to` before, appended to out
 * in tile order, filtered as the scan's (mx_answer_near) and marked sent: the same set
 * mx_answer's scan gives (D12).  The search starts
 * at Q's first vertex, whose neighbours include a conflicting point whenever one exists, and
 * crosses conflicting points only; Q's vertices are never tested (the scan skips them too). */
/* the tile points not sent to `to` yet, in tile order, marked sent: a complete answer (D12) */
static gtet_status lift_dump(run *R, int to, vec *out)
{
    for (size_t j = 0; j < R->m; j++) {
        if (mx_sent(R, j, to)) continue;
        mpt *o = mx_vec_push(out);
        if (!o || mx_mark_sent(R, j, to) < 0)
            return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        *o = R->sp[j];
    }
    return GTET_OK;
}

gtet_status mx_answer_lift(run *R, lift *L, const query *Q, int to, vec *out)
{
    uint32_t v[4];
    /* every tile point was sent to `to` before: nothing to answer (6c) */
    if (R->nsent[to] == R->m) return GTET_OK;
    /* this round's searches for `to` went over the limit: the rest of the tile (GTET_MPI_DUMP=off:
     * never, for the tests that compare the answers with the scans') */
    if (L->work[to] > (uint64_t)LIFT_DUMP_LIMIT * R->m && mx_env_mode("GTET_MPI_DUMP") >= 0)
        return lift_dump(R, to, out);
    for (int i = 0; i < 4; i++)
        if (!map_find(L, Q->id[i], &v[i])) return mx_answer(R, Q, to, out);
    /* a tet of DT(X): no point of X conflicts with it (P4), the answer is empty */
    uint32_t key[4] = {v[0], v[1], v[2], v[3]};
    sort4u(key);
    if (tet_in(L, key)) return GTET_OK;
    if (++L->cur == 0) {
        memset(L->stamp, 0, (L->nx + 1) * sizeof *L->stamp);
        L->cur = 1;
    }
    for (int i = 0; i < 4; i++) L->stamp[v[i]] = L->cur;
    size_t nk = 0;
    for (size_t h = 0;; h++) {
        uint32_t x = h == 0 ? v[0] : L->queue[h - 1];
        for (size_t k = L->adj0[x]; k < L->adj0[x + 1]; k++) {
            uint32_t u = L->adj[k];
            if (L->stamp[u] == L->cur) continue;
            L->stamp[u] = L->cur;
            R->c.st->answer_tests++;
            L->work[to]++;
            if (gtet_insphere_sos(Q->p[0], Q->p[1], Q->p[2], Q->p[3], lift_point(R, L, u)) <= 0)
                continue;
            if (nk == L->qcap) {
                size_t cap = L->qcap ? 2 * L->qcap : 256;
                uint32_t *q = mx_realloc(L->queue, cap * sizeof *q);
                if (!q) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
                L->queue = q;
                L->qcap = cap;
            }
            L->queue[nk++] = u;
        }
        if (h == nk) break;
    }
    /* the conflicting tile points, in tile order (the search's order depends on DT(X)'s tet
     * order, which threads may change) */
    size_t w = 0;
    for (size_t k = 0; k < nk; k++)
        if (L->queue[k] < R->m && !mx_sent(R, L->queue[k], to)) L->queue[w++] = L->queue[k];
    mpi_sort(L->queue, w, sizeof *L->queue, cmp_u32);
    size_t n0 = out->n;
    for (size_t k = 0; k < w; k++) {
        uint32_t j = L->queue[k];
        mpt *o = mx_vec_push(out);
        if (!o) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        *o = R->sp[j];
        o->id = j;   /* the tile index until mx_answer_near, as the scan's */
    }
    return mx_answer_near(R, to, out, n0, 0);
}
