/* mpi_cavity.c -- a later round's cavity in the local mesh DT(S): C, the tets, and H, the hull
 * facets, some new point of N conflicts with (proofs/distributed.md D10: each new point located
 * by a walk and its conflict region grown over the conflict graph; D4: a grid over the new
 * points and conservative balls only prune, the exact predicates decide).  mpi_patch.c then
 * triangulates the cavity. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_patch.h"

/* the new points in a grid of cells over their box (start: CSR offsets, idx: S indices) */
typedef struct ngrid {
    double box[6], inv[3];
    int g[3];
    uint32_t *start, *idx;
} ngrid;

static int ncell(const ngrid *G, int k, double x)
{
    double t = (x - G->box[k]) * G->inv[k];
    if (!(t >= 0)) return 0;
    if (t >= G->g[k]) return G->g[k] - 1;
    return (int)t;
}

static size_t ncell_id(const ngrid *G, const double *x)
{
    return ((size_t)ncell(G, 2, x[2]) * (size_t)G->g[1] + (size_t)ncell(G, 1, x[1])) *
               (size_t)G->g[0] + (size_t)ncell(G, 0, x[0]);
}

static int ngrid_build(ngrid *G, const run *R, size_t n_old)
{
    size_t nn = R->ns - n_old;
    for (int k = 0; k < 3; k++) {
        G->box[k] = INFINITY;
        G->box[3 + k] = -INFINITY;
    }
    for (size_t i = n_old; i < R->ns; i++)
        for (int k = 0; k < 3; k++) {
            G->box[k] = fmin(G->box[k], R->sp[i].x[k]);
            G->box[3 + k] = fmax(G->box[3 + k], R->sp[i].x[k]);
        }
    /* ~nn/8 cells: N lies along the tile's faces (a sheet in its box), so most cells of a
     * finer grid are empty and a ball's range visits them one by one (NOTES E192) */
    int g = (int)fmin(64, fmax(1, ceil(0.5 * cbrt((double)nn))));
    size_t cells = 1;
    for (int k = 0; k < 3; k++) {
        double e = G->box[3 + k] - G->box[k];
        G->g[k] = e > 0 ? g : 1;
        G->inv[k] = e > 0 ? G->g[k] / e : 0;
        if (!isfinite(G->inv[k])) {
            G->g[k] = 1;
            G->inv[k] = 0;
        }
        cells *= (size_t)G->g[k];
    }
    G->start = mx_calloc(cells + 1, sizeof *G->start);
    G->idx = mx_malloc((nn + 1) * sizeof *G->idx);
    if (!G->start || !G->idx) return -1;
    for (size_t i = n_old; i < R->ns; i++) G->start[ncell_id(G, R->sp[i].x) + 1]++;
    for (size_t c = 0; c < cells; c++) G->start[c + 1] += G->start[c];
    for (size_t i = n_old; i < R->ns; i++) G->idx[G->start[ncell_id(G, R->sp[i].x)]++] = (uint32_t)i;
    for (size_t c = cells; c > 0; c--) G->start[c] = G->start[c - 1];
    G->start[0] = 0;
    return 0;
}

/* does a new point conflict with tet v?  (cells the conservative ball reaches, D4); *work
 * counts the exact tests */
static int tet_conflicts(const run *R, const ngrid *G, const uint32_t *v, uint64_t *work)
{
    const mpt *sp = R->sp;
    ball B;
    mx_tet_ball(sp[v[0]].x, sp[v[1]].x, sp[v[2]].x, sp[v[3]].x, &B);
    if (!mx_ball_meets_box(&B, G->box)) return 0;
    int lo[3] = {0, 0, 0}, hi[3] = {G->g[0] - 1, G->g[1] - 1, G->g[2] - 1};
    if (!B.all) {
        /* only the cells the ball reaches inside N's box (its points' exact bounding box): a
         * flat tet's huge ball spans the grid, whose cells are mostly empty (N lies along the
         * tile's faces) */
        double h[3];
        mx_ball_reach(G->box, G->box + 3, &B, h);
        for (int k = 0; k < 3; k++) {
            lo[k] = ncell(G, k, B.c[k] - h[k]);
            hi[k] = ncell(G, k, B.c[k] + h[k]);
        }
    }
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                size_t c = ((size_t)z * (size_t)G->g[1] + (size_t)y) * (size_t)G->g[0] + (size_t)x;
                for (uint32_t j = G->start[c]; j < G->start[c + 1]; j++) {
                    const double *p = sp[G->idx[j]].x;
                    if (!B.all) {
                        double d0 = p[0] - B.c[0], d1 = p[1] - B.c[1], d2 = p[2] - B.c[2];
                        if (sqrt(d0 * d0 + d1 * d1 + d2 * d2) > B.r * (1 + 1e-9)) continue;
                    }
                    ++*work;
                    if (gtet_insphere_sos(sp[v[0]].x, sp[v[1]].x, sp[v[2]].x, sp[v[3]].x, p) > 0)
                        return 1;
                }
            }
    return 0;
}

static int find_cavity_walk(patch *X, const ngrid *G);

/* mark C and H: the tets and the hull facets some new point conflicts with (exact
 * predicates), by locating the new points (D10) or, should that fail, by testing every tet
 * (the grid and the balls only prune, D4); -1 out of memory, 1 over the growth's budget (the
 * caller triangulates from scratch) */
int mx_find_cavity(patch *X)
{
    const run *R = X->R;
    const mpt *sp = R->sp;
    ngrid G;
    memset(&G, 0, sizeof G);
    int w = ngrid_build(&G, R, X->n_old) != 0 ? -1 : find_cavity_walk(X, &G);
    if (w != 0) {
        free(G.start);
        free(G.idx);
        return w < 0 ? -1 : w == 2 ? 1 : 0;
    }
    R->c.st->scans++;
    for (size_t t = 0; t < X->nt; t++) {
        const uint32_t *v = X->tv + 4 * t;
        uint64_t work = 0;
        if (tet_conflicts(R, &G, v, &work)) X->cf[t] |= 16;
        for (int f = 0; f < 4; f++) {
            if (X->nb[4 * t + f] != GTET_NO_TET) continue;
            uint32_t h[3];
            mx_hull_facet(R, v, f, h);
            if (!mx_halfspace_meets_box(sp[h[0]].x, sp[h[1]].x, sp[h[2]].x, G.box)) continue;
            for (size_t i = X->n_old; i < R->ns; i++)
                if (gtet_ghost_conflict(sp[h[0]].x, sp[h[1]].x, sp[h[2]].x, sp[i].x) > 0) {
                    X->cf[t] |= (uint8_t)(1u << f);
                    break;
                }
        }
    }
    free(G.start);
    free(G.idx);
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* C and H by locating each new point and growing its conflict region (D10)                   */
/* ------------------------------------------------------------------------------------------ */

/* a node of the conflict graph: tet t (5t + 4) or the ghost tet on t's hull facet f (5t + f) */
#define TET_NODE(t) (5 * (uint64_t)(t) + 4)
#define GHOST_NODE(t, f) (5 * (uint64_t)(t) + (uint64_t)(f))

/* does point p conflict with the node (exact: gtet_insphere_sos, gtet_ghost_conflict)? */
static int node_conflicts(const patch *X, uint64_t node, const double *p)
{
    const mpt *sp = X->R->sp;
    const uint32_t *v = X->tv + 4 * (size_t)(node / 5);
    int f = (int)(node % 5);
    if (f == 4) return gtet_insphere_sos(sp[v[0]].x, sp[v[1]].x, sp[v[2]].x, sp[v[3]].x, p) > 0;
    uint32_t h[3];
    mx_hull_facet(X->R, v, f, h);
    return gtet_ghost_conflict(sp[h[0]].x, sp[h[1]].x, sp[h[2]].x, p) > 0;
}

static uint64_t xorshift(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

#define WALK_STEPS 65536

/* stochastic visibility walk from tet t to p: the tet whose closed region holds p (*hf = -1)
 * or a tet with a hull facet *hf that p is strictly beyond; NONE when it takes too long */
static uint32_t walk_to(const patch *X, uint32_t t, const double *p, int *hf, uint64_t *rng)
{
    const mpt *sp = X->R->sp;
    for (int step = 0; step < WALK_STEPS; step++) {
        const uint32_t *v = X->tv + 4 * (size_t)t;
        int r = (int)(xorshift(rng) & 3), f = -1;
        for (int k = 0; k < 4 && f < 0; k++) {
            int g = (r + k) & 3;
            const double *q[4] = {sp[v[0]].x, sp[v[1]].x, sp[v[2]].x, sp[v[3]].x};
            q[g] = p;
            if (gtet_orient3d(q[0], q[1], q[2], q[3]) < 0) f = g;   /* beyond facet g */
        }
        if (f < 0) {
            *hf = -1;
            return t;
        }
        uint32_t u = X->nb[4 * (size_t)t + f];
        if (u == GTET_NO_TET) {
            *hf = f;
            return t;
        }
        t = u;
    }
    return NONE;
}

/* the ghost tet across edge (a, b) of the hull facet opposite slot f of tet t, c the facet's
 * third vertex: turn around the edge through the tets until the other hull facet; NONE64 when
 * the turn does not end (an inconsistent mesh: fall back) */
#define NONE64 UINT64_MAX
static uint64_t ghost_across(const patch *X, uint32_t t, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t x = c;
    for (size_t step = 0; step <= X->nt; step++) {
        const uint32_t *v = X->tv + 4 * (size_t)t;
        int i = 0, y = -1;
        while (i < 4 && v[i] != x) i++;
        for (int j = 0; j < 4; j++)
            if (v[j] != a && v[j] != b && v[j] != x) y = j;
        if (i == 4 || y < 0) return NONE64;
        uint32_t u = X->nb[4 * (size_t)t + i];
        if (u == GTET_NO_TET) return GHOST_NODE(t, i);
        x = v[y];
        t = u;
    }
    return NONE64;
}

/* does some new point conflict with the node?  tets: tet_conflicts (the conservative ball over
 * the grid, D4); ghosts: a plane filter before the exact hull rule (orient3d(a, b, c, p) as
 * (u x w) . d with u = b - a, w = c - a, d = p - a: a value below -1e-12 times its permanent is
 * negative exactly, Shewchuk's bound being (7 + 56 eps) eps ~ 1.6e-15 times it; NaN and
 * infinities from overflow fail the comparison and go to the exact predicate) */
static int node_conflicts_any(const patch *X, const ngrid *G, uint64_t node, uint64_t *work)
{
    const run *R = X->R;
    const mpt *sp = R->sp;
    const uint32_t *v = X->tv + 4 * (size_t)(node / 5);
    if (node % 5 == 4) return tet_conflicts(R, G, v, work);
    uint32_t h[3];
    mx_hull_facet(R, v, (int)(node % 5), h);
    const double *a = sp[h[0]].x, *b = sp[h[1]].x, *c = sp[h[2]].x;
    double u[3], w[3], n[3], m[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        w[k] = c[k] - a[k];
    }
    for (int k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        n[k] = u[k1] * w[k2] - u[k2] * w[k1];
        m[k] = fabs(u[k1] * w[k2]) + fabs(u[k2] * w[k1]);
    }
    for (size_t i = X->n_old; i < R->ns; i++) {
        const double *p = sp[i].x;
        double d0 = p[0] - a[0], d1 = p[1] - a[1], d2 = p[2] - a[2];
        double val = n[0] * d0 + n[1] * d1 + n[2] * d2;
        double perm = m[0] * fabs(d0) + m[1] * fabs(d1) + m[2] * fabs(d2);
        if (val < -1e-12 * perm) continue;
        ++*work;
        if (gtet_ghost_conflict(a, b, c, p) > 0) return 1;
    }
    return 0;
}

/* the growth's state: per tet, bit 4 tested as a tet, bit f tested as the ghost on facet f */
typedef struct grow {
    uint8_t *tested;
    uint64_t *queue;
    size_t nq, cap;
    uint64_t work, budget;   /* the exact tests "some point of N" made, and the most it may
                                make before the patch gives way to a new triangulation */
} grow;

/* queue a node in conflict (marking it in C or H); 0, or -1 out of memory */
static int queue_node(patch *X, grow *Q, uint64_t node)
{
    if (Q->nq == Q->cap) {
        size_t cap = Q->cap ? 2 * Q->cap : 4096;
        uint64_t *q = mx_realloc(Q->queue, cap * sizeof *q);
        if (!q) return -1;
        Q->queue = q;
        Q->cap = cap;
    }
    Q->queue[Q->nq++] = node;
    X->cf[node / 5] |= (uint8_t)(node % 5 == 4 ? 16 : 1u << (node % 5));
    return 0;
}

/* test a node not tested yet and queue it if some new point conflicts with it; 0, -1 out of
 * memory, 2 over the budget */
static int visit(patch *X, const ngrid *G, grow *Q, uint64_t node)
{
    uint8_t bit = (uint8_t)(node % 5 == 4 ? 16 : 1u << (node % 5));
    if (Q->tested[node / 5] & bit) return 0;
    Q->tested[node / 5] |= bit;
    int c = node_conflicts_any(X, G, node, &Q->work);
    if (Q->work > Q->budget) return 2;
    return c ? queue_node(X, Q, node) : 0;
}

/* the conflict graph's neighbours of a node (D10): a tet's four (tets, or ghosts on its hull
 * facets), a ghost's tet and the three ghosts across its edges; their number, or -1 when a turn
 * around a hull edge does not end (fall back) */
static int node_neighbours(const patch *X, uint64_t node, uint64_t nbr[4])
{
    uint32_t t = (uint32_t)(node / 5);
    const uint32_t *v = X->tv + 4 * (size_t)t;
    int f = (int)(node % 5);
    if (f == 4) {
        for (int g = 0; g < 4; g++) {
            uint32_t u = X->nb[4 * (size_t)t + g];
            nbr[g] = u == GTET_NO_TET ? GHOST_NODE(t, g) : TET_NODE(u);
        }
        return 4;
    }
    nbr[0] = TET_NODE(t);
    uint32_t h[3];
    int j = 0;
    for (int i = 0; i < 4; i++)
        if (i != f) h[j++] = v[i];
    for (int e = 0; e < 3; e++) {
        nbr[1 + e] = ghost_across(X, t, h[(e + 1) % 3], h[(e + 2) % 3], h[e]);
        if (nbr[1 + e] == NONE64) return -1;
    }
    return 4;
}

/* from the queued seeds, every node some new point conflicts with that is connected to them
 * through such nodes (tets by facets, a ghost to its tet and to the ghosts across its edges);
 * 1 ok, 0 fall back (a turn around a hull edge failed), -1 OOM, 2 over the budget */
static int grow_cavity(patch *X, const ngrid *G, grow *Q)
{
    for (size_t at = 0; at < Q->nq; at++) {
        uint64_t nbr[4];
        int k = node_neighbours(X, Q->queue[at], nbr);
        if (k < 0) return 0;
        for (int i = 0; i < k; i++) {
            int r = visit(X, G, Q, nbr[i]);
            if (r != 0) return r == 2 ? 2 : -1;
        }
    }
    return 1;
}

/* a node in conflict with p near the walk's end (tet t, hull facet hf or -1): t, a ghost on
 * it, or a neighbour; NONE64 if none (fall back) */
static uint64_t seed_node(const patch *X, uint32_t t, int hf, const double *p)
{
    if (hf >= 0) return node_conflicts(X, GHOST_NODE(t, hf), p) ? GHOST_NODE(t, hf) : NONE64;
    if (node_conflicts(X, TET_NODE(t), p)) return TET_NODE(t);
    for (int g = 0; g < 4; g++) {
        uint32_t u = X->nb[4 * (size_t)t + g];
        uint64_t n = u == GTET_NO_TET ? GHOST_NODE(t, g) : TET_NODE(u);
        if (node_conflicts(X, n, p)) return n;
    }
    return NONE64;
}

/* C and H grown from one node in conflict with each new point, found by a walk that locates
 * the point (D10): the cost is in C, H, their boundary and the walks, not the mesh.  The new
 * points are visited cell by cell (each walk starts where the last one ended).  1 done, 0
 * fall back to the scan (X->cf reset), -1 out of memory, 2 over the budget */
static int find_cavity_walk(patch *X, const ngrid *G)
{
    const run *R = X->R;
    size_t nn = R->ns - X->n_old;
    if (X->nt == 0) return 0;
    grow Q = {mx_calloc(X->nt + 1, 1), NULL, 0, 0, 0, 0};
    int ok = Q.tested ? 1 : -1;
    /* the tests of "some point of N" may make 2 exact tests per point of S (uniform points
     * make ~0.015, NOTES.md E212); where every ball holds most of N (points on a sphere) the
     * floating filters pass all of N at each node of the cavity and its boundary, and
     * triangulating S u N from scratch costs less (D9; GTET_MPI_PATCH_BUDGET=off: no limit,
     * for the tests) */
    Q.budget = mx_env_mode("GTET_MPI_PATCH_BUDGET") < 0 ? UINT64_MAX
                                                         : 2 * (uint64_t)R->ns + 4096;
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    uint32_t t = 0;
    for (size_t i = 0; i < nn && ok == 1; i++) {
        const double *p = R->sp[G->idx[i]].x;
        int hf;
        t = walk_to(X, t, p, &hf, &rng);
        uint64_t seed = t == NONE ? NONE64 : seed_node(X, t, hf, p);
        if (seed == NONE64) {
            ok = 0;
        } else {
            uint8_t bit = (uint8_t)(seed % 5 == 4 ? 16 : 1u << (seed % 5));
            if (!(Q.tested[seed / 5] & bit)) {
                Q.tested[seed / 5] |= bit;
                if (queue_node(X, &Q, seed) < 0) ok = -1;
            }
        }
    }
    if (ok == 1) ok = grow_cavity(X, G, &Q);
    free(Q.tested);
    free(Q.queue);
    if (ok == 0) memset(X->cf, 0, X->nt);
    return ok;
}
