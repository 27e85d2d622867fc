/* triangulate.c -- gtet_triangulate: validate -> BRIO order -> insert -> compact -> (check).
 *
 * The pipeline of DESIGN.md, serial for now (a parallel insertion on Moore-curve partitions
 * replaces the insertion loop in the parallel kernel).  Every failure frees what was built and
 * returns a status with details in opts->error; nothing is printed, nothing exits.
 */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "../sort/sort.h"
#include "../kernel/finalize.h"
#include "../kernel/kmesh.h"
#include "../kernel/parallel.h"
#include "../mesh/mesh.h"
#include "../validate/validate.h"

#define BRIO_FIRST 2048
#define BRIO_RATIO 6.0
#define BRIO_SEED 0x67696761746574ULL  /* the result does not depend on it */

static void add_counters(gtet_pred_counters *s, const gtet_pred_counters *a)
{
    s->orient_calls += a->orient_calls;
    s->orient_exact += a->orient_exact;
    s->orient_int += a->orient_int;
    s->orient_gmp += a->orient_gmp;
    s->orient_zero += a->orient_zero;
    s->insphere_calls += a->insphere_calls;
    s->insphere_exact += a->insphere_exact;
    s->insphere_int += a->insphere_int;
    s->insphere_gmp += a->insphere_gmp;
    s->insphere_zero += a->insphere_zero;
    s->sos_calls += a->sos_calls;
    for (int i = 0; i < 4; i++) s->sos_depth[i] += a->sos_depth[i];
}

/* A thread's log of the perturbation's decisions, on cache lines of its own: a thread writes
 * its log at every decision (about 15 per point on an integer grid), and two threads' logs
 * must not share a line. */
typedef struct klog {
    _Alignas(64) pred_sos_log log;
} klog;

/* Order of the merged degeneracy records: kind, vertex ids in argument order, term, sign. */
static int cmp_degeneracy(const void *pa, const void *pb)
{
    const gtet_degeneracy *a = pa, *b = pb;
    if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
    for (int i = 0; i < 5; i++)
        if (a->vertex[i] != b->vertex[i]) return a->vertex[i] < b->vertex[i] ? -1 : 1;
    if (a->term != b->term) return a->term < b->term ? -1 : 1;
    return (a->sign > b->sign) - (a->sign < b->sign);
}

/* The threads' logs of the perturbation's decisions -> res->degen: internal ids mapped to
 * mesh ids (internal id i is mesh vertex order[i]), sorted, the first `limit` kept.  Each log
 * counted every decision its thread's counters did (sos.c: decided), so the totals must
 * agree with sos_calls, the sum of those counters; anything else is a broken invariant. */
static gtet_status merge_degeneracies(gtet_mesh *res, const klog *logs, int threads,
                                      const uint32_t *order, size_t limit, uint64_t sos_calls)
{
    uint64_t total = 0;
    size_t n = 0;
    for (int k = 0; k < threads; k++) {
        if (logs[k].log.failed & PRED_SOS_LOG_FOREIGN) return GTET_ERR_INTERNAL;
        if (logs[k].log.failed) return GTET_ERR_OUT_OF_MEMORY;
        total += logs[k].log.total;
        n += logs[k].log.n;
    }
    if (total != sos_calls) return GTET_ERR_INTERNAL;
    res->degen_total = total;
    if (n == 0) return GTET_OK;
    gtet_degeneracy *all = malloc(n * sizeof *all);
    if (!all) return GTET_ERR_OUT_OF_MEMORY;
    size_t j = 0;
    for (int k = 0; k < threads; k++)
        for (size_t i = 0; i < logs[k].log.n; i++) {
            gtet_degeneracy r = logs[k].log.rec[i];
            for (int q = 0; q < r.npoints; q++) r.vertex[q] = order[r.vertex[q]];
            all[j++] = r;
        }
    qsort(all, n, sizeof *all, cmp_degeneracy);
    if (n > limit) {
        n = limit;
        gtet_degeneracy *shrunk = realloc(all, (n ? n : 1) * sizeof *all);
        if (shrunk) all = shrunk;
    }
    res->degen = all;
    res->n_degen = n;
    return GTET_OK;
}

static gtet_status fail(gtet_error *err, gtet_status s, const char *what)
{
    if (err && err->status != s) kval_error(err, s, SIZE_MAX, -1, "%s: %s", what, gtet_status_str(s));
    return s;
}

gtet_status gtet_triangulate(const double *xyz, size_t n, const gtet_options *opts_in,
                             gtet_mesh **out)
{
    gtet_options opts;
    if (opts_in) opts = *opts_in;
    else gtet_options_init(&opts);
    gtet_error *err = opts.error;
    if (err) {
        memset(err, 0, sizeof *err);
        err->index = SIZE_MAX;
        err->dimension = -1;
    }
    if (!out) return fail(err, GTET_ERR_ARGUMENT, "gtet_triangulate: mesh pointer is NULL");
    *out = NULL;
    if (!xyz && n) return fail(err, GTET_ERR_ARGUMENT, "gtet_triangulate: points are NULL");
    if (opts.threads < 0)
        return fail(err, GTET_ERR_ARGUMENT, "gtet_triangulate: negative thread count");
    if (n >= KM_MAX_VERTICES) {
        kval_error(err, GTET_ERR_TOO_LARGE, SIZE_MAX, -1,
                   "%zu points exceed the 2^31-1 vertex limit", n);
        return GTET_ERR_TOO_LARGE;
    }
    double t_start = omp_get_wtime();
    int threads = opts.threads ? opts.threads : omp_get_max_threads();
    gtet_status s = kval_finite(xyz, n, threads, err);
    if (s != GTET_OK) return s;

    gtet_mesh *res = calloc(1, sizeof *res);
    if (!res) return fail(err, GTET_ERR_OUT_OF_MEMORY, "allocating the result");
    res->n_points = n;
    s = kval_dedup(xyz, n, threads, &res->vertices, &res->input_map, &res->n_vertices, err);
    if (s != GTET_OK) {
        gtet_mesh_free(&res);
        return s;
    }
    size_t nv = res->n_vertices;
    gtet_pred_counters cnt0;
    memset(&cnt0, 0, sizeof cnt0);
    double t_validated = omp_get_wtime();

    uint32_t *order = malloc((nv ? nv : 1) * sizeof *order);
    if (!order) {
        gtet_mesh_free(&res);
        return fail(err, GTET_ERR_OUT_OF_MEMORY, "allocating the insertion order");
    }
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) order[i] = (uint32_t)i;
    size_t round_end[64];
    int nrounds = 0;
    /* with threads, the BRIO's Moore keys also colour the vertices (kpar_init), unless one
     * cell holds more than a quarter of a slice of some round (one point far away, heavy
     * tails): the keys cannot cut such a round evenly, and the kernel keys the tight box with
     * 21 bits instead (1M points + one at 10^6, -t 2: 1.45 s against 2.29 with the BRIO's
     * keys; ten Gaussian clusters of 10^-9..1 keep them, 10% per cell: 1.86 s against 2.15;
     * NOTES.md 2026-11-24) */
    uint64_t *bkeys = NULL;
    int bbits = 0;
    double crowd = 0.0;
    s = sort_brio_keys(res->vertices, 3, order, nv, BRIO_SEED, BRIO_FIRST, BRIO_RATIO, round_end,
                       &nrounds, threads, threads > 1 ? &bkeys : NULL, &bbits, NULL, &crowd);
    if (crowd > 0.25 / threads) {
        free(bkeys);
        bkeys = NULL;
    }
    if (s != GTET_OK) {
        free(order);
        gtet_mesh_free(&res);
        return fail(err, s, "sorting the points");
    }
    double t_sorted = omp_get_wtime();

    size_t pos[4];
    s = kval_first_simplex(res->vertices, order, nv, pos, &cnt0, err);
    if (s != GTET_OK) {
        free(bkeys);
        free(order);
        gtet_mesh_free(&res);
        return s;
    }
    /* about 6.5 tets per vertex plus the hull's ghosts; grows if needed */
    size_t hint = 7 * nv + 64;
    if (hint > KM_MAX_SLOTS) {
        if (nv > KM_MAX_SLOTS / 7) {
            free(bkeys);
            free(order);
            gtet_mesh_free(&res);
            kval_error(err, GTET_ERR_TOO_LARGE, SIZE_MAX, -1,
                       "%zu distinct points exceed the 2^30 - 1 tet-slot limit", nv);
            return GTET_ERR_TOO_LARGE;
        }
        hint = KM_MAX_SLOTS;
    }
    /* The kernel works on a copy of the vertices in insertion order (internal id i is output
     * vertex order[i]): consecutive insertions then touch neighbouring memory, as HXT gets by
     * sorting its vertex records.  Output ids are restored after the compaction. */
    double *sv = malloc((nv ? 3 * nv : 3) * sizeof *sv);
    uint32_t *ids = malloc((nv ? nv : 1) * sizeof *ids);
    if (!sv || !ids) {
        free(bkeys);
        free(sv);
        free(ids);
        free(order);
        gtet_mesh_free(&res);
        return fail(err, GTET_ERR_OUT_OF_MEMORY, "allocating the sorted vertices");
    }
    const double *rv = res->vertices;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) memcpy(sv + 3 * i, rv + 3 * (size_t)order[i], 3 * sizeof *sv);
    kmesh m;
    s = km_init(&m, sv, nv, hint, threads);
    if (threads > 255) threads = 255;
    kctx *ctx = aligned_alloc(_Alignof(kctx), (size_t)threads * sizeof *ctx);
    if (ctx) memset(ctx, 0, (size_t)threads * sizeof *ctx);
    kpar P;
    memset(&P, 0, sizeof P);
    if (!ctx) s = GTET_ERR_OUT_OF_MEMORY;
    for (int k = 0; ctx && k < threads; k++) kctx_init(&ctx[k], &m, (uint64_t)k + 1);
    /* one log per thread (no sharing, no locks); their points are the sorted copy sv */
    klog *logs = NULL;
    if (opts.degeneracies && ctx) {
        logs = aligned_alloc(_Alignof(klog), (size_t)threads * sizeof *logs);
        if (!logs) s = GTET_ERR_OUT_OF_MEMORY;
        for (int k = 0; logs && k < threads; k++) {
            memset(&logs[k], 0, sizeof logs[k]);
            logs[k].log.base = sv;
            logs[k].log.nv = nv;
            logs[k].log.limit = opts.degeneracy_limit;
            ctx[k].sos_log = &logs[k].log;
        }
    }
    if (s == GTET_OK) {
        s = kpar_init(&P, &m, ctx, threads, bkeys, bbits);  /* owns bkeys from here */
    } else {
        free(bkeys);
    }
    if (s == GTET_OK)
        s = km_first_tet(&ctx[0], (uint32_t)pos[0], (uint32_t)pos[1], (uint32_t)pos[2],
                         (uint32_t)pos[3]);
    /* the rounds, without the four vertices of the first tet: position i moves down by the
     * number of those before it (a round's end likewise) */
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) {
        if (i == pos[0] || i == pos[1] || i == pos[2] || i == pos[3]) continue;
        ids[i - (size_t)((pos[0] < i) + (pos[1] < i) + (pos[2] < i) + (pos[3] < i))] = (uint32_t)i;
    }
    for (int r = 0; r < nrounds; r++) {
        const size_t e = round_end[r];
        round_end[r] = e - (size_t)((pos[0] < e) + (pos[1] < e) + (pos[2] < e) + (pos[3] < e));
    }
    res->rounds = calloc((size_t)(nrounds > 0 ? nrounds : 1), sizeof *res->rounds);
    if (!res->rounds && s == GTET_OK) s = GTET_ERR_OUT_OF_MEMORY;
    P.progress = opts.progress;
    P.progress_user = opts.progress_user;
    P.total = nv;
    P.done = 4;
    for (int k = 0; k < nrounds && s == GTET_OK; k++) {
        size_t b = k ? round_end[k - 1] : 0;
        s = kpar_round(&P, ids + b, round_end[k] - b, &res->rounds[k]);
    }
    free(ids);
    if (opts.progress && s == GTET_OK) opts.progress(opts.progress_user, 1.0);
    double t_inserted = omp_get_wtime();
    size_t slots_peak = m.cap;
    if (s == GTET_OK) s = km_finalize(&m, &res->tets, &res->neighbors, &res->n_tets, &res->n_hull_facets,
                                      threads);
    if (s == GTET_OK) {  /* output vertex ids */
        uint32_t *tv = res->tets;
        const size_t n4 = 4 * res->n_tets;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && n4 > 262144)
        for (size_t i = 0; i < n4; i++) tv[i] = order[tv[i]];
    }
    if (s == GTET_OK && logs) {
        uint64_t sos_calls = cnt0.sos_calls;
        for (int k = 0; k < threads; k++) sos_calls += ctx[k].cnt.sos_calls;
        s = merge_degeneracies(res, logs, threads, order, opts.degeneracy_limit, sos_calls);
    }
    for (int k = 0; logs && k < threads; k++) free(logs[k].log.rec);
    free(logs);
    free(order);
    free(sv);
    add_counters(&res->stats.pred, &cnt0);
    res->stats.tets_created = 5;
    for (int k = 0; ctx && k < threads; k++) {
        add_counters(&res->stats.pred, &ctx[k].cnt);
        res->stats.tets_created += ctx[k].tets_created;
        res->stats.walk_steps += ctx[k].walk_steps;
        res->stats.walk_fallbacks += ctx[k].walk_fallbacks;
        kctx_free(&ctx[k]);
    }
    free(ctx);
    kpar_free(&P);
    km_free(&m);
    if (s != GTET_OK) {
        gtet_mesh_free(&res);
        return fail(err, s, "inserting the points");
    }
    double t_done = omp_get_wtime();
    gtet_stats *st = &res->stats;
    st->seconds_validate = t_validated - t_start;
    st->seconds_sort = t_sorted - t_validated;
    st->seconds_insert = t_inserted - t_sorted;
    st->seconds_finalize = t_done - t_inserted;
    st->seconds_total = t_done - t_start;
    st->threads = threads;
    st->num_rounds = nrounds;
    /* working mesh: 16 B vertex ids + 16 B neighbours per slot, plus the
     * vertices (24 B each) and their 1-byte cavity-local ids; the dead flag is a bit of tv */
    st->peak_bytes = slots_peak * 32 + nv * 25 + n * 4;
    st->bytes_per_tet = res->n_tets ? (slots_peak * 32 + nv * 25) / res->n_tets : 0;
    if (opts.check) {
        gtet_check_report rep;
        s = gtet_check(res, xyz, n, 0, &rep);
        if (s != GTET_OK) {
            if (err) {
                kval_error(err, s, SIZE_MAX, -1, "%s", rep.message);
            }
            gtet_mesh_free(&res);
            return s;
        }
    }
    *out = res;
    return GTET_OK;
}
