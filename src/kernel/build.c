/* build.c -- kbuild_run: the kernel stage, from an insertion order to the result's tets.
 *
 * start: the vertices copied into insertion order (internal id i is mesh vertex order[i], so
 *   consecutive insertions touch neighbouring memory; from KBUILD_HOLD_ONCE_MIN points on the
 *   result's own copy is freed until finish, so the coordinates are held once at the run's
 *   peak), the working mesh (kmesh.h)
 *   with room for about 7 tets per vertex, one insertion context per thread, the parallel state
 *   (parallel.h), the first tet and its four ghosts;
 * rounds: each BRIO round through kpar_round (parallel passes, then serial);
 * finish: the parallel state and per-vertex marks freed, compaction into the result arrays
 *   (finalize.c), the result's vertices scattered back from the sorted copy (big runs), mesh vertex ids
 *   restored, the threads' logs of the perturbation's decisions merged, the counters summed.
 * Whatever step fails, kbuild_release frees everything the run allocated (one cleanup path).
 */
#include "build.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "finalize.h"
#include "kmesh.h"
#include "parallel.h"

/* A thread's log of the perturbation's decisions, on cache lines of its own: a thread writes
 * its log at every decision (about 15 per point on an integer grid), and two threads' logs
 * must not share a line. */
typedef struct klog {
    _Alignas(64) pred_sos_log log;
} klog;

/* Everything one run allocates besides the result. */
typedef struct kbuild {
    const kbuild_in *in;
    gtet_mesh *res;
    size_t nv;
    int threads;         /* at most 255 from kbuild_start on (colours are bytes) */
    uint64_t *keys;      /* the BRIO's keys until kpar_init takes them */
    double *sv;          /* vertices in insertion order */
    uint32_t *ids;       /* the rounds' internal ids, without the first tet's four */
    size_t round_end[64];
    kmesh m;
    kctx *ctx;           /* one per thread */
    klog *logs;          /* one per thread, or NULL */
    kpar P;
} kbuild;

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
    s->insphere_int122 += a->insphere_int122;
}

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

/* The contexts and, when recording, one log per thread (no sharing, no locks; their points
 * are the sorted copy sv). */
static gtet_status alloc_contexts(kbuild *b)
{
    const int T = b->threads;
    b->ctx = aligned_alloc(_Alignof(kctx), (size_t)T * sizeof *b->ctx);
    if (!b->ctx) return GTET_ERR_OUT_OF_MEMORY;
    memset(b->ctx, 0, (size_t)T * sizeof *b->ctx);
    for (int k = 0; k < T; k++) kctx_init(&b->ctx[k], &b->m, (uint64_t)k + 1);
    if (!b->in->degeneracies) return GTET_OK;
    b->logs = aligned_alloc(_Alignof(klog), (size_t)T * sizeof *b->logs);
    if (!b->logs) return GTET_ERR_OUT_OF_MEMORY;
    for (int k = 0; k < T; k++) {
        memset(&b->logs[k], 0, sizeof b->logs[k]);
        b->logs[k].log.base = b->sv;
        b->logs[k].log.nv = b->nv;
        b->logs[k].log.limit = b->in->degeneracy_limit;
        b->ctx[k].sos_log = &b->logs[k].log;
    }
    return GTET_OK;
}

/* The first `slots` slots of the tet arrays mapped now, by every thread (NOTES.md E111): right
 * after the result's vertices were freed, so that the pages come from what they gave back
 * (cheap on a machine whose host takes freed memory back a little later) rather than from
 * fresh memory faulted one page at a time by the insertion.  A Delaunay tetrahedrization of nv
 * points in general position has at least nv - 3 tets, and the slots also hold the ghosts, so
 * nv slots are used by every run: this never makes resident what the run would not. */
static void prefault_slots(kmesh *m, size_t slots, int threads)
{
    const size_t huge = (size_t)2 << 20;
    if (slots > m->cap) slots = m->cap;
    const size_t bytes = 4 * slots * sizeof *m->tv;
    const int T = threads < 1 ? 1 : threads;
    const size_t part = ((bytes + (size_t)T - 1) / (size_t)T + huge - 1) & ~(huge - 1);
    char *arr[2] = {(char *)m->tv, (char *)m->tn};
#pragma omp parallel for num_threads(T) schedule(static) if (T > 1)
    for (int k = 0; k < 2 * T; k++) {
        const size_t lo = (size_t)(k / 2) * part;
        if (lo < bytes) (void)base_populate(arr[k % 2] + lo, bytes - lo < part ? bytes - lo : part);
    }
}

/* The working mesh with its first tet, the contexts, the parallel state, and the rounds'
 * internal ids: every position but the first tet's four, position i moved down by the number
 * of those before it (a round's end likewise). */
static gtet_status kbuild_start(kbuild *b, gtet_error *err)
{
    const kbuild_in *in = b->in;
    const size_t nv = b->nv, *pos = in->first;
    int threads = b->threads;
    /* about 6.5 tets per vertex plus the hull's ghosts; grows if needed.  With threads, what
     * the last BRIO round's reserve will ask (parallel.c kpar_round: the slots in use + 8 per
     * pending point + two blocks a thread; 7.5-7.9 per point measured on uniform, clustered,
     * scanned and spherical sets): growing there would move the arrays off their huge pages
     * (kmesh.c first_arrays).  The pages never touched stay unmapped. */
    size_t hint = 7 * nv + 64;
    if (threads > 1)
        hint = 8 * nv + 64 + (size_t)(threads < BASE_MAX_THREADS ? threads : BASE_MAX_THREADS) * 2 * KM_SLOT_BLOCK;
    if (hint > KM_MAX_SLOTS) {
        if (nv > KM_MAX_SLOTS / 7) {
            base_error(err, GTET_ERR_TOO_LARGE, SIZE_MAX, -1,
                       "%zu distinct points exceed the 2^30 - 1 tet-slot limit", nv);
            return GTET_ERR_TOO_LARGE;
        }
        hint = KM_MAX_SLOTS;
    }
    b->sv = base_alloc_big((nv ? 3 * nv : 3) * sizeof *b->sv);
    b->ids = base_alloc_big((nv ? nv : 1) * sizeof *b->ids);  /* NOTES.md E110 */
    if (!b->sv || !b->ids)
        return base_fail(err, GTET_ERR_OUT_OF_MEMORY, "allocating the sorted vertices");
    base_hugepages(b->sv, 3 * nv * sizeof *b->sv);  /* read at random (E19) */
    const double *rv = b->res->vertices;
    const uint32_t *order = in->order;
    double *sv = b->sv;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) memcpy(sv + 3 * i, rv + 3 * (size_t)order[i], 3 * sizeof *sv);
    /* sv holds every coordinate (order is a permutation of 0..nv-1): for a big run
     * kbuild_finish scatters them back (24 B per point less at the peak; NOTES.md E14) */
    if (nv >= KBUILD_HOLD_ONCE_MIN) {
        free(b->res->vertices);
        b->res->vertices = NULL;
    }
    gtet_status s = km_init(&b->m, sv, nv, hint, threads, in->wide);
    if (s != GTET_OK) return s;
    if (nv >= KBUILD_HOLD_ONCE_MIN) prefault_slots(&b->m, nv, threads);
    b->m.grow_guard = in->grow_guard;
    b->m.grow_user = in->grow_user;
    if (b->threads > BASE_MAX_THREADS) b->threads = BASE_MAX_THREADS;
    s = alloc_contexts(b);
    if (s != GTET_OK) return s;
    s = kpar_init(&b->P, &b->m, b->ctx, b->threads, b->keys, in->key_bits);
    b->keys = NULL;  /* kpar_init owns them from here, also after a failure */
    if (s != GTET_OK) return s;
    s = km_first_tet(&b->ctx[0], (uint32_t)pos[0], (uint32_t)pos[1], (uint32_t)pos[2],
                     (uint32_t)pos[3]);
    if (s != GTET_OK) return s;
    uint32_t *ids = b->ids;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) {
        if (i == pos[0] || i == pos[1] || i == pos[2] || i == pos[3]) continue;
        ids[i - (size_t)((pos[0] < i) + (pos[1] < i) + (pos[2] < i) + (pos[3] < i))] = (uint32_t)i;
    }
    for (int r = 0; r < in->num_rounds; r++) {
        const size_t e = in->round_end[r];
        b->round_end[r] = e - (size_t)((pos[0] < e) + (pos[1] < e) + (pos[2] < e) + (pos[3] < e));
    }
    b->res->rounds = calloc((size_t)(in->num_rounds > 0 ? in->num_rounds : 1),
                            sizeof *b->res->rounds);
    return b->res->rounds ? GTET_OK : GTET_ERR_OUT_OF_MEMORY;
}

/* The BRIO rounds, in order; the callbacks run here, on the calling thread. */
static gtet_status kbuild_rounds(kbuild *b)
{
    const kbuild_in *in = b->in;
    b->P.progress = in->progress;
    b->P.progress_user = in->progress_user;
    b->P.cancel = in->cancel;
    b->P.cancel_user = in->cancel_user;
    b->P.total = b->nv;
    b->P.done = 4;
    for (int k = 0; k < in->num_rounds; k++) {
        const size_t first = k ? b->round_end[k - 1] : 0;
        if (in->cancel && in->cancel(in->cancel_user)) return GTET_ERR_CANCELLED;
        const double t0 = in->round_done ? omp_get_wtime() : 0.0;
        gtet_status s = kpar_round(&b->P, b->ids + first, b->round_end[k] - first,
                                   &b->res->rounds[k]);
        if (s != GTET_OK) return s;
        if (in->round_done)
            in->round_done(in->round_user, k, in->num_rounds, &b->res->rounds[k],
                           omp_get_wtime() - t0);
    }
    return GTET_OK;
}

/* The result's vertices in mesh order again: vertices[order[i]] = sv[i]; sv freed. */
static gtet_status restore_vertices(kbuild *b)
{
    const size_t nv = b->nv;
    const uint32_t *order = b->in->order;
    double *v = base_alloc_big((nv ? 3 * nv : 3) * sizeof *v);
    if (!v) return GTET_ERR_OUT_OF_MEMORY;
    base_hugepages(v, 3 * nv * sizeof *v);  /* written at random (NOTES.md E19) */
    const double *sv = b->sv;
#pragma omp parallel for num_threads(b->threads) schedule(static) if (b->threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) memcpy(v + 3 * (size_t)order[i], sv + 3 * i, 3 * sizeof *v);
    b->res->vertices = v;
    free(b->sv);
    b->sv = NULL;
    return GTET_OK;
}

/* Compaction, the result's vertices, mesh vertex ids, degeneracy records.  What only the
 * insertion needs goes first, so that neither step raises the run's peak. */
static gtet_status kbuild_finish(kbuild *b)
{
    gtet_mesh *res = b->res;
    const uint32_t *order = b->in->order;
    const int threads = b->threads;
    kpar_free(&b->P);
    free(b->m.vloc);
    b->m.vloc = NULL;
    /* the result's vertices first, right after the frees above: their pages then come from
     * what those gave back (NOTES.md E111); the compaction needs neither sv nor vloc */
    gtet_status s = res->vertices ? GTET_OK : restore_vertices(b);
    if (s == GTET_OK)
        s = km_finalize(&b->m, &res->tets, &res->neighbors, &res->n_tets, &res->n_hull_facets,
                        threads, order);  /* the tets' vertices as mesh ids */
    if (s != GTET_OK) return s;
    if (!b->logs) return GTET_OK;
    uint64_t sos_calls = res->stats.pred.sos_calls;
    for (int k = 0; k < threads; k++) sos_calls += b->ctx[k].cnt.sos_calls;
    return merge_degeneracies(res, b->logs, threads, order, b->in->degeneracy_limit, sos_calls);
}

/* The counters into res->stats, and every allocation of the run freed (any state). */
static void kbuild_release(kbuild *b)
{
    gtet_stats *st = &b->res->stats;
    for (int k = 0; b->logs && k < b->threads; k++) free(b->logs[k].log.rec);
    free(b->logs);
    free(b->sv);
    free(b->ids);
    free(b->keys);
    st->tets_created = 5;
    for (int k = 0; b->ctx && k < b->threads; k++) {
        add_counters(&st->pred, &b->ctx[k].cnt);
        st->tets_created += b->ctx[k].tets_created;
        st->walk_steps += b->ctx[k].walk_steps;
        st->walk_fallbacks += b->ctx[k].walk_fallbacks;
        kctx_free(&b->ctx[k]);
    }
    free(b->ctx);
    kpar_free(&b->P);
    km_free(&b->m);
}

gtet_status kbuild_run(const kbuild_in *in, gtet_mesh *res, double *t_inserted, gtet_error *err)
{
    kbuild b;
    memset(&b, 0, sizeof b);
    b.in = in;
    b.res = res;
    b.nv = res->n_vertices;
    b.threads = in->threads;
    b.keys = in->keys;
    gtet_status s = kbuild_start(&b, err);
    if (s == GTET_OK) s = kbuild_rounds(&b);
    free(b.ids);  /* before the compaction: its peak memory is the run's */
    b.ids = NULL;
    if (s == GTET_OK && in->progress) in->progress(in->progress_user, 1.0);
    *t_inserted = omp_get_wtime();
    const size_t slots_peak = b.m.cap;
    if (s == GTET_OK) s = kbuild_finish(&b);
    kbuild_release(&b);
    gtet_stats *st = &res->stats;
    st->threads = b.threads;
    st->num_rounds = in->num_rounds;
    /* working mesh: 16 B vertex ids + 16 B neighbours per slot, plus the vertices (24 B
     * each) and their 1-byte cavity-local ids; the dead flag is a bit of tv */
    st->peak_bytes = slots_peak * 32 + b.nv * 25 + res->n_points * 4;
    st->bytes_per_tet = res->n_tets ? (slots_peak * 32 + b.nv * 25) / res->n_tets : 0;
    return s;
}
