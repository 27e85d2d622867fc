/* mpi_ghosts.c -- steps 5-6 of gtet_triangulate_mpi: the local set S (tile points, then
 * ghosts) and its triangulation, the seeded ghost layer, and the rounds of conflict queries
 * until no rank receives a new point (proofs/distributed.md D3, D5, D8). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "mpi/mpi_internal.h"

/* ------------------------------------------------------------------------------------------ */
/* the local set S and its triangulation                                                      */
/* ------------------------------------------------------------------------------------------ */

/* add a point of rank `owner` to S unless present; returns 1 added, 0 present, -1 OOM.
 * The tiles are disjoint and every point of this tile is in S from the seeding on
 * (mx_step_seed, which adds them directly), so a point of this rank is present and only the
 * other tiles' points go through R->have: a set of the ghosts, not of all of S */
static int s_add(run *R, const mpt *p, int owner)
{
    if (owner == R->c.rank) return 0;
    int a = mx_hs_add(&R->have, p->id);
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
    free(R->ptv);
    free(R->ptn);
    R->ptv = R->ptn = NULL;
    R->qfrom = 0;   /* every tet is this round's */
    if (R->m == 0) return GTET_OK;
    for (int attempt = 0; attempt < 2; attempt++) {
        double *xyz = mx_malloc(3 * R->ns * sizeof *xyz);
        if (!xyz) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t i = 0; i < R->ns; i++) memcpy(xyz + 3 * i, R->sp[i].x, 3 * sizeof(double));
        /* the arrays with room for the output's 64-bit rows (E130); S holds distinct points
         * (one per vertex id: the duplicate step, D1), so the kernel's own duplicate pass is
         * skipped */
        gtet_error e;
        gtet_status s = mx_triangulate_own(&R->lopt, xyz, R->ns, &R->mesh, &e);
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

/* rank q's seeded layer width: R->layer times its tile's mean spacing, from the gathered box
 * and count only (the same double on every rank) */
double mx_layer_width(const run *R, int q)
{
    const double *bx = R->box + 6 * q;
    double vol = 1, emax = 0;
    for (int k = 0; k < 3; k++) emax = fmax(emax, bx[3 + k] - bx[k]);
    for (int k = 0; k < 3; k++) vol *= fmax(bx[3 + k] - bx[k], emax * 1e-3);
    double delta = R->layer * cbrt(vol / (double)R->tcount[q]);
    return isfinite(delta) ? delta : 0;
}

/* Does rank q's seeded layer around this tile's box hold every point of the ball?  Rank q sent
 * this rank each tile point x with fl(mx_box_dist(B_me, x)) <= layer_width(q) (mx_step_seed).
 * For x in the ball, the exact distance is at most dist(B_me, c) + r, and mx_box_dist's
 * rounding is far below the relative 1e-9 margins (a subtraction, squares, a sum and a square
 * root: a few ulps); so then every point of tile q in the ball is in S already (D3). */
static int seed_covers(const run *R, const ball *B, int q)
{
    if (B->all) return 0;
    double d = mx_box_dist(R->box + 6 * R->c.rank, B->c);
    return (d * (1 + 1e-9) + B->r * (1 + 1e-9)) * (1 + 1e-9) <= mx_layer_width(R, q) * (1 - 1e-9);
}

gtet_status mx_step_seed(run *R, double layer)
{
    int P = R->c.size, me = R->c.rank;
    vec *out = mx_calloc((size_t)P, sizeof *out);
    size_t *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    gtet_status s = (out && rcnt) ? GTET_OK : mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY,
                                                      "out of memory");
    R->layer = layer;
    if (s == GTET_OK && R->m) {
        /* room for the tile and a ghost layer up front: no rehashing, fewer page faults;
         * the set of S's ids holds the ghosts only (s_add) */
        size_t want = R->m + R->m / 4 + 64, cap = 64;
        while (cap < 2 * (R->m / 4 + 64)) cap *= 2;
        mpt *sp = mx_malloc(want * sizeof *sp);
        int *so = mx_malloc(want * sizeof *so);
        R->sent_any = mx_calloc((R->m + 63) / 64, sizeof *R->sent_any);
        R->nsent = mx_calloc((size_t)P, sizeof *R->nsent);
        if (!sp || !so || !R->sent_any || !R->nsent || mx_hs_grow(&R->have, cap) != 0) {
            free(sp);
            free(so);
            s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        } else {
            R->sp = sp;
            R->sown = so;
            R->scap = want;
        }
    }
    /* the tile, distinct (D1), in the grid's cell order: S's first m points */
    if (s == GTET_OK) s = mx_grid_build(R);
    if (s == GTET_OK) s = mx_grid_far(R);
    if (s == GTET_OK && R->m) {
        for (size_t i = 0; i < R->m; i++) R->sown[i] = me;
        R->ns = R->m;
    }
    if (s == GTET_OK && R->m) {
        /* the layer: `layer` times the tile's mean spacing; every rank computes the same
         * width from the gathered box and count (layer_width), so a receiver knows exactly
         * which of this tile's points it got (seed_covers) */
        double delta = mx_layer_width(R, me);
        for (int q = 0; q < P; q++) out[q].rs = sizeof(mpt);
        for (size_t i = 0; i < R->m && s == GTET_OK; i++)
            for (int q = 0; q < P; q++) {
                if (q == me || R->tcount[q] == 0) continue;
                if (mx_box_dist(R->box + 6 * q, R->sp[i].x) > delta) continue;
                mpt *o = mx_vec_push(&out[q]);
                if (!o || mx_mark_sent(R, i, q) < 0) {
                    s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
                    break;
                }
                *o = R->sp[i];
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

void mx_sort4(uint64_t *k)
{
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[j - 1] > k[j]; j--) {
            uint64_t t = k[j];
            k[j] = k[j - 1];
            k[j - 1] = t;
        }
}

/* ghost order of the facet opposite f of local tet t: orient3d(a,b,c,apex) < 0 */
void mx_hull_facet(const run *R, const uint32_t *tv, int f, uint32_t out[3])
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
#define QPF 16

static gtet_status make_queries(run *R, vec *out)
{
    mx_upper_clean();   /* after the kernel and the agreement (E220) */
    int P = R->c.size, me = R->c.rank;
    for (int q = 0; q < P; q++) out[q].rs = sizeof(query);
    size_t nt;
    const uint32_t *tv, *nb;
    mx_local_mesh(R, &nt, &tv, &nb);
    if (!tv) {
        free(R->prev);
        R->prev = NULL;
        R->nprev = 0;
        return GTET_OK;
    }
    vec keys = {NULL, 0, 0, 4 * sizeof(uint64_t)};
    size_t m = R->m;
    /* only the tets this round made: a tet kept from an earlier round was queried or
     * certified in the round it appeared, and that decision depends on the tet, the boxes and
     * the layer widths only (D3) */
    for (size_t t = R->qfrom; t < nt; t++) {
        const uint32_t *v = tv + 4 * t;
        /* the points of a tet QPF further on fetched now: S's records are read at random
         * (tets in the kernel's order, points in the tile's), a cache miss each (NOTES E131) */
        if (t + QPF < nt)
            for (int i = 0; i < 4; i++) __builtin_prefetch(&R->sp[v[4 * QPF + i]]);
        if (v[0] >= m && v[1] >= m && v[2] >= m && v[3] >= m) continue;
        /* a far tile vertex: the tet's circumball misses every other tile's box (D11) */
        int far = 0;
        const uint64_t *fb = R->gr.far;
        for (int i = 0; i < 4; i++) far |= v[i] < m && (fb[v[i] >> 6] >> (v[i] & 63) & 1);
        /* the tet */
        for (int pass = far; pass < 5; pass++) {
            query Q;
            uint64_t key[4];
            ball B;
            if (pass == 0) {
                /* the ball from S's records where they lie: the query's copy is made only
                 * for a tet that is sent (~1 in 800 at 4M), not for every ball (NOTES E219) */
                mx_tet_ball(R->sp[v[0]].x, R->sp[v[1]].x, R->sp[v[2]].x, R->sp[v[3]].x, &B);
            } else {
                int f = pass - 1;
                if (nb[4 * t + f] != GTET_NO_TET) continue;
                uint32_t h[3];
                mx_hull_facet(R, v, f, h);
                if (h[0] >= m && h[1] >= m && h[2] >= m) continue;
                for (int i = 0; i < 3; i++) {
                    memcpy(Q.p[i], R->sp[h[i]].x, sizeof Q.p[i]);
                    Q.id[i] = key[i] = R->sp[h[i]].id;
                }
                memset(Q.p[3], 0, sizeof Q.p[3]);
                Q.id[3] = key[3] = NOID;
            }
            int any = 0;
            for (int q = 0; q < P; q++) {
                if (q == me || R->tcount[q] == 0) continue;
                const double *bx = R->box + 6 * q;
                if (pass == 0 ? !mx_ball_meets_box(&B, bx)
                              : !mx_halfspace_meets_box(Q.p[0], Q.p[1], Q.p[2], bx))
                    continue;
                /* every point of tile q the ball holds was seeded here: certified (D3) */
                if (pass == 0 && seed_covers(R, &B, q)) continue;
                if (!any) {
                    any = 1;
                    if (pass == 0)
                        for (int i = 0; i < 4; i++) {
                            memcpy(Q.p[i], R->sp[v[i]].x, sizeof Q.p[i]);
                            Q.id[i] = key[i] = R->sp[v[i]].id;
                        }
                    mx_sort4(key);
                    uint64_t *kk = mx_vec_push(&keys);
                    if (!kk) goto oom;
                    memcpy(kk, key, sizeof key);
                    /* queried in the previous round and still here: certified (D3) */
                    if (R->prev && bsearch(key, R->prev, R->nprev, sizeof *R->prev, cmp_key4))
                        break;
                }
                query *o = mx_vec_push(&out[q]);
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

gtet_status mx_step_rounds(run *R)
{
    int P = R->c.size;
    gtet_status s = GTET_OK;
    /* the answers' triangulation, kept while it serves (mx_lift_build) */
    lift L;
    memset(&L, 0, sizeof L);
    vec *out = mx_calloc((size_t)P, sizeof *out);
    size_t *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    if (!out || !rcnt) s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
    size_t n_old = 0;
    for (int round = 1;; round++) {
        double t0 = mx_now();
        /* later rounds re-triangulate only the new points' cavity (D9) when they can */
        int done = 0;
        if (round > 1) s = mx_patch(R, n_old, &done);
        if (s == GTET_OK && !done) {
            s = triangulate_local(R);
            R->c.st->rebuilds += round > 1 && R->m;
        }
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
        /* where the scans would be quadratic, the ball queries are answered from DT(X) (D12) */
        s = mx_lift_build(R, qs, rt, &L);
        mx_upper_clean();   /* after the exchange and DT(X)'s kernel (E220) */
        size_t k = 0;
        for (int q = 0; q < P && s == GTET_OK; q++)
            for (size_t i = 0; i < rcnt[q] && s == GTET_OK; i++, k++)
                s = L.on && qs[k].id[3] != NOID ? mx_answer_lift(R, &L, &qs[k], q, &out[q])
                                                : mx_answer(R, &qs[k], q, &out[q]);
        free(rb);
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        if ((s = exchange_vecs(R, out, sizeof(mpt), &rb, rcnt, &rt)) != GTET_OK) goto done;
        uint64_t added = 0, gadded = 0;
        n_old = R->ns;
        s = s_add_received(R, rb, rcnt, &added);
        free(rb);
        if ((s = mx_agree(&R->c, s)) != GTET_OK) goto done;
        MPI_Allreduce(&added, &gadded, 1, MPI_UINT64_T, MPI_SUM, R->c.comm);
        R->c.st->seconds_exchange += mx_now() - t0;
        if (gadded == 0) break;   /* every queried tet is certified: S is final (D3) */
    }
done:
    mx_lift_free(&L);
    if (out)
        for (int q = 0; q < P; q++) free(out[q].p);
    free(out);
    free(rcnt);
    return s;
}
