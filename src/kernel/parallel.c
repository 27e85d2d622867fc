/* parallel.c -- concurrent insertion of one BRIO round on Moore-curve partitions (paper §4).
 *
 * A pass: the pending points of the round get Moore keys (in a round's first pass and first
 * retry the BRIO's, on the box of all points, which the round's BRIO order already follows, so
 * nothing is computed or sorted (the BRIO refines a crowded cell by these keys, E257) -- or,
 * when even those crowd one key, 21-bit keys on the tight box computed once per run; on an
 * enlarged and shifted box in later passes, where
 * only the vertices of the mesh are re-keyed), are sorted by key and cut into one slice per
 * thread, never between equal keys (slices.c): at the coarsest Moore-cell boundary within 1/64
 * of a slice of equal count, in a round's first pass from the origin on the loop whose equal-count cuts are
 * coarsest (a dense cluster's faces: E12; else halfway along the curve between two slices'
 * neighbouring points).  The colour boundaries lie between two slices' neighbouring
 * points (on that cell boundary, or halfway along the curve); when the mesh's tets cross
 * fewer than 3/4 as often a median plane across one axis, the first pass takes slabs instead
 * (NOTES.md E70: the top-level Moore split of two slices can fall across a flat shell's thin
 * axis, where every inner tet crosses it).  They colour every vertex the mesh holds by the end of the round (colour = the slice range its key falls
 * in); vertices of later rounds are never read.  Thread k inserts the points of slice k, and an
 * insertion goes ahead only if the walk and every tet of the cavity stay within tets of
 * thread k (all four vertices of colour k, or three once the run has switched: km_owned;
 * km_insert defers the point otherwise, having written nothing).  proofs/parallel.md shows
 * that two threads then never write, or write and read, the same memory: no tet is two
 * threads', a tet next to one of thread k's is no other thread's, and the only tets two
 * threads both write are outer neighbours, in different neighbour slots.  With three of four
 * (after the run's first failed pass) a vertex every tet shares -- the apex over a plane, a
 * far outlier -- does not stop every other thread (NOTES.md E9).  Fresh slots come from per-thread blocks
 * claimed with one atomic capture; the arrays grow only between passes.
 *
 * Adaptive, as in paper §4.2, with alpha = inserted / pending points of the pass, n threads:
 *   alpha <= 1/n       -> the rest of the round is inserted sequentially,
 *   1/n < alpha <= 1/6 -> half the threads (reduction),
 *   otherwise          -> same threads, new partitions: slabs between median planes
 *                         across the axis whose cuts meet the fewest pending points
 *                         (NOTES.md E40, E178; where slabs
 *                         are refused, the round's first retry cuts the same curve in the
 *                         middles of the first pass's slices' deferred points, E6, E20,
 *                         later ones use an enlarged, shifted box).
 * Termination (proofs/termination.md): a parallel pass that goes on inserts more than a 1/n
 * fraction of the pending points, so their number shrinks geometrically, and the sequential
 * insertion (no colours) always succeeds.
 *
 * Obligations of proofs/parallel.md, where they are met: O1 colours and slice bounds computed
 * before the region, slices never split equal keys (kpar_slices in slices.c, pass_parallel); O2 ownership checked before
 * a tet is marked dead, O8 no scan fallback, O10 rollback (km_insert / walk / rollback in
 * insert.c); O3 one thread: no colours (insert_serial); O4 start and restart tets found
 * read-only before the region's barrier (starts.c: kpar_find_start, kpar_find_checkpoints: a
 * thread whose last try was deferred walks on from the next checkpoint, NOTES.md E13;
 * kpar_find_runs: in a slab pass a
 * thread walks on from a tet located for each point where the curve comes back into its slab,
 * E100); O5 slots from free lists and atomic block claims that never pass
 * the capacity (ensure_room); O6 arrays grow only between passes (kpar_round); O7 the retry
 * policy above (kpar_round); O9 vloc only for vertices of the thread's colour
 * (adjacency_fast_foreign for cavities with a foreign vertex, adjacency_hash for big ones);
 * O11 first error in a shared status (critical), read atomically between insertions; O12 per-
 * thread counters, the slot counter is the only shared one (atomic).
 */
#include "parallel.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "../base/base.h"
#include "starts.h"

#define KEY_BITS KPAR_KEY_BITS  /* per axis: 63-bit Moore keys (slices.h) */
#define MIN_PER_THREAD 2048   /* fewer points per thread: fewer threads */
/* In a pass, a thread that has tried at least max(GIVE_UP_MIN, its slice / GIVE_UP_PROBE)
 * points and has so far inserted fewer than 1 in GIVE_UP_RATE of its tries (checked after every
 * try from then on) defers the rest of its slice untried: when cavities
 * span the whole domain (points on a paraboloid: alpha = 0.001) the pass would otherwise walk
 * and roll back every point before the round goes serial, slower than one thread (NOTES.md
 * E3).  Deferring is always allowed (O7, T5). */
#define GIVE_UP_PROBE 16
#define GIVE_UP_MIN 1024
#define GIVE_UP_RATE 8

size_t kpar_test_stop_after = 0;  /* parallel.h */

/* A pass after the first retry colours every vertex in the mesh again (a slab by one coordinate,
 * NOTES.md E40; a re-keying on a new box when slabs are refused), and its points are the hard
 * ones (big cavities, long walks): with fewer pending points than nmesh / SERIAL_TAIL it is one
 * serial pass instead (NOTES.md E4: 32 when every such pass re-keyed; 128 with slabs, whose
 * second and third retries on the Bunny insert 2/3 and 4/5 of their points in parallel). */
#define SERIAL_TAIL 128
/* Run starts of a slab pass located before it, per slice (slabs.h kpar_runs, kpar_slab_split; NOTES.md
 * E100): the Bunny's 833k-point round has ~650 a slice; more are thinned to the longest gaps. */
#define RUNS_PER_SLICE 2048

gtet_status kpar_init(kpar *P, kmesh *m, kctx *ctx, int threads, uint64_t *keys, int key_bits)
{
    memset(P, 0, sizeof *P);
    P->m = m;
    P->ctx = ctx;
    P->threads = threads;
    P->colour = base_alloc_big(m->nv ? m->nv : 1);
    if (keys && key_bits >= 1 && key_bits <= KEY_BITS) {
        P->keys = keys;
        P->key_shift = 3 * (KEY_BITS - key_bits);
        P->have_keys = 1;
    } else {
        free(keys);
        P->keys = base_alloc_big((m->nv ? m->nv : 1) * sizeof *P->keys);
    }
    P->skeys = base_alloc_big((m->nv ? m->nv : 1) * sizeof *P->skeys);
    if (threads > 1) {  /* untouched until a point is deferred (the memory guard counts it) */
        P->hint = base_alloc_big((m->nv ? m->nv : 1) * sizeof *P->hint);
        if (!P->hint) return GTET_ERR_OUT_OF_MEMORY;
    }
    const size_t nth = (size_t)(threads < 1 ? 1 : threads > BASE_MAX_THREADS ? BASE_MAX_THREADS : threads);
    P->runs.cap = RUNS_PER_SLICE;
    P->runs.at = malloc(nth * RUNS_PER_SLICE * sizeof *P->runs.at);
    P->run_tet = malloc(nth * RUNS_PER_SLICE * sizeof *P->run_tet);
    if (!P->colour || !P->keys || !P->skeys || !P->runs.at || !P->run_tet)
        return GTET_ERR_OUT_OF_MEMORY;
    return GTET_OK;
}

void kpar_free(kpar *P)
{
    free(P->colour);
    free(P->keys);
    free(P->skeys);
    free(P->pk);
    free(P->tk);
    free(P->ti);
    free(P->runs.at);
    free(P->run_tet);
    free(P->hint);
    P->runs.at = NULL;
    P->run_tet = NULL;
    P->hint = NULL;
    P->colour = NULL;
    P->keys = NULL;
    P->skeys = NULL;
    P->pk = P->tk = NULL;
    P->ti = NULL;
}

/* Any live tet, for a serial insertion after parallel passes moved things around. */
static void serial_start(kctx *c)
{
    const kmesh *m = c->m;
    if (c->last < m->nt && !km_dead(m, c->last)) return;
    for (size_t t = 0; t < m->nt; t++)
        if (!km_dead(m, t)) {
            c->last = (uint32_t)t;
            return;
        }
}

static inline double dist2(const double *a, const double *b)
{
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

/* Start p's walk at t when t's first vertex is nearer p than c->last's (both live tets: a
 * hint's slot may hold another tet by now, and any live tet is a start). */
static inline void nearer_start(kctx *c, uint32_t p, uint32_t t)
{
    const kmesh *m = c->m;
    if (dist2(km_pt(m, p), km_pt(m, m->tv[4 * (size_t)t] & ~KM_DEAD)) <
        dist2(km_pt(m, p), km_pt(m, m->tv[4 * (size_t)c->last] & ~KM_DEAD)))
        c->last = t;
}

/* The rest of a round on one thread.  After a parallel pass (use_hints: the pass wrote a hint
 * for every point it left) a walk may start from the tet the point's last try began its cavity
 * at (E177): the points left are scattered along the old colour boundaries, and the walk from
 * the previous point's tet is about twice as long there (NOTES.md E254).  Without colours
 * every live tet is a start. */
static gtet_status insert_serial(kpar *P, const uint32_t *pts, size_t np, int use_hints)
{
    kctx *c = &P->ctx[0];
    const kmesh *m = c->m;
    c->colour = NULL;
    serial_start(c);
    for (size_t i = 0; i < np; i++) {
        int deferred;
        if (use_hints) {
            const uint32_t t = P->hint[pts[i]];
            if (t < m->nt && !km_dead(m, t)) nearer_start(c, pts[i], t);
        }
        gtet_status s = km_insert(c, pts[i], &deferred);
        if (s != GTET_OK) return s;
        if (deferred) return GTET_ERR_INTERNAL;  /* serial insertion never defers */
        if (((P->done + i) & 0xffff) == 0) {
            if (P->progress)
                P->progress(P->progress_user, (double)(P->done + i) / (double)P->total);
            if (P->cancel && P->cancel(P->cancel_user)) return GTET_ERR_CANCELLED;
        }
    }
    P->done += np;
    return GTET_OK;
}

/* Record s as the pass's error unless one is there (O11). */
static void pass_error(int *status, gtet_status s)
{
#pragma omp critical(gtet_status)
    if (*status == GTET_OK) {
#pragma omp atomic write
        *status = (int)s;
    }
}

/* Thread c's slice pts[b..e) of a pass, inside the parallel region: its deferred points are
 * moved to pts[b..b+*nd) in order.  A thread whose insertions almost all fail stops trying
 * (GIVE_UP); so does every thread once one has failed (the shared *status, read atomically). */

static void insert_slice(kctx *c, uint32_t *pts, size_t b, size_t e, int have_start,
                         const kpar_restarts *R, uint32_t *hint, int use_hints, int *status,
                         int *stop, size_t *nd_out, size_t *tried_out, size_t *stop_out)
{
    const kmesh *m = c->m;
    const uint32_t *ck = R->ck;
    int stale = 0;  /* the last try was deferred: c->last may be a tet no walk gets out of */
    size_t next_run = 0;
    int next_ck = 1;
    const size_t nck = (size_t)R->nck;
    size_t next_at = b + (e - b) / nck;
    const size_t probe = (e - b) / GIVE_UP_PROBE > GIVE_UP_MIN ? (e - b) / GIVE_UP_PROBE
                                                               : GIVE_UP_MIN;
    size_t nd = 0, tried = 0;
    int give_up = 0;
    c->last_ghost = UINT32_MAX;  /* O13: a hull search starts only from this pass's own ghost */
    const size_t test_stop = stop ? kpar_test_stop_after : 0;  /* parallel.h: tests only */
    size_t i = b;
    for (; i < e; i++) {
        int deferred = 1;
        gtet_status s = GTET_OK;
        int failed, stopped = 0;
#pragma omp atomic read
        failed = *status;
        if (stop) {
#pragma omp atomic read
            stopped = *stop;
        }
        if (stopped && e - i >= KPAR_REBALANCE_MIN) break;  /* the rest goes to the rebalancing */
        if (test_stop && tried == test_stop && c->mine == 0) {
#pragma omp atomic write
            *stop = 1;  /* tests: a stop the other threads see with most of their slices left */
        }
        if (i == next_at && (size_t)next_ck < nck) {
            const uint32_t t = ck[next_ck];
            if (stale && t != UINT32_MAX && !km_dead(m, t)) c->last = t;
            next_ck++;
            next_at = b + (e - b) * (size_t)next_ck / nck;
        }
        if (next_run < R->nruns && i == b + R->run_at[next_run]) {
            /* the curve came back into the slab: walk on from its run's own tet, which the
             * previous point's walk may not reach within this thread's tets (E100) */
            const uint32_t t = R->run_tet[next_run++];
            if (t != UINT32_MAX && !km_dead(m, t)) c->last = t;
        }
        if (use_hints && have_start) {
            /* the tet this point's cavity started from in the last pass (E177): checked before
             * the barrier to be live and this thread's (kpar_check_hints, O4), and since then
             * only this thread has written it (O2), so a live one is still a tet to start
             * from; taken when its first vertex is nearer the point than c->last's (its slot
             * may hold another tet by now; c->last is this thread's too: a start, a restart
             * or a tet its insertions made) */
            const uint32_t t = hint[pts[i]];
            if (t != UINT32_MAX && !km_dead(m, t)) nearer_start(c, pts[i], t);
        }
        c->defer_hint = UINT32_MAX;
        int tried_now = 0;
        if (have_start && !failed && !c->out_of_room && !give_up) {
            s = km_insert(c, pts[i], &deferred);
            stale = deferred;
            tried++;
            tried_now = 1;
            give_up = tried >= probe && (tried - nd - deferred) * GIVE_UP_RATE < tried;
        }
        if (s != GTET_OK) pass_error(status, s);
        if (deferred || s != GTET_OK) {
            if (hint) hint[pts[i]] = tried_now && s == GTET_OK ? c->defer_hint : UINT32_MAX;
            pts[b + nd++] = pts[i];
        }
    }
    if (stop && i == e && have_start && !give_up && !c->out_of_room) {
#pragma omp atomic write
        *stop = 1;  /* this slice is done: the others leave their long rests (KPAR_REBALANCE_MIN) */
    }
    *nd_out = nd;
    *tried_out = tried;
    *stop_out = i;
}

/* The threads' region of a pass on slices pts[begin[k]..end[k]) whose colours are set (O1):
 * thread k's deferred points end at pts[begin[k] .. + ndef[k]), its untried rest (a stop,
 * stop != NULL) is pts[stop_at[k] .. end[k]).  Returns the first error of any thread. */
static gtet_status pass_region(kpar *P, uint32_t *pts, const size_t begin[], const size_t end[],
                               int nth, int use_hints, int *stop, size_t ndef[], size_t ntried[],
                               size_t stop_at[], int *out_of_room)
{
    kmesh *m = P->m;
    int status = GTET_OK;  /* the first error of any thread (a gtet_status) */
    int room = 0;
#pragma omp parallel num_threads(nth)
    {
        int tid = omp_get_thread_num();
        kctx *c = &P->ctx[tid];
        c->colour = P->colour;
        c->mine = (uint8_t)tid;
        c->own_min = P->own3 ? 3 : 4;
        c->out_of_room = 0;
        int have_start = kpar_find_start(c, nth, pts + begin[tid], end[tid] - begin[tid]);
        kpar_restarts R = {.run_at = P->runs.at + (size_t)tid * P->runs.cap,
                      .run_tet = P->run_tet + (size_t)tid * P->runs.cap,
                      .nruns = P->runs.n[tid],
                      .nck = kpar_checkpoints(end[tid] - begin[tid])};
        kpar_find_checkpoints(c, pts + begin[tid], end[tid] - begin[tid], R.nck, R.ck);
        kpar_find_runs(c, pts + begin[tid], end[tid] - begin[tid], &R);
        if (use_hints) kpar_check_hints(c, pts + begin[tid], end[tid] - begin[tid], P->hint);
#pragma omp barrier
        insert_slice(c, pts, begin[tid], end[tid], have_start, &R, P->hint, use_hints, &status,
                     stop, &ndef[tid], &ntried[tid], &stop_at[tid]);
        gtet_status fs = km_flush_block(c);
        if (fs != GTET_OK) pass_error(&status, fs);
        if (c->out_of_room) {
#pragma omp atomic write
            room = 1;
        }
        c->colour = NULL;
    }
    if (m->nt > m->cap) m->nt = m->cap;  /* failed block claims went past the end */
    *out_of_room |= room;
    return (gtet_status)status;
}

/* One parallel pass over pts[0..np) with `nth` threads; the mesh holds (or will hold, at the
 * end of this round) the vertices 0..nmesh-1.  Deferred points are moved to the front of pts
 * and counted in *left.  A round's first pass (on Moore slices or on slabs) stops when a
 * thread has done its slice and rebalances the others' rests (rebalance.c: the threads'
 * speeds differ from run to run on a shared machine, and equal counts only estimate equal
 * costs). */
static gtet_status pass_parallel(kpar *P, uint32_t *pts, size_t np, size_t nmesh, int nth,
                                 unsigned pass, size_t *left, size_t *attempts, int *out_of_room,
                                 uint64_t *rebalanced)
{
    size_t begin[256], end[256];
    const uint64_t *keys;
    int sh = 0;
    kpar_pass_partition(P, pts, np, nmesh, nth, pass, begin, end, &keys, &sh);
    size_t ndef[256], ntried[256], stop_at[256];
    int room = 0, stop = 0;
    /* the pending points of a round's later passes were all deferred or left in the pass
     * before, which wrote their hints; a round's first pass has none */
    const int use_hints = P->hint != NULL && pass > 0;
    const int rebalance = pass == 0 && ((keys && P->cuts.nth == nth) || P->slab_first);
    gtet_status s = pass_region(P, pts, begin, end, nth, use_hints, rebalance ? &stop : NULL,
                                ndef, ntried, stop_at, &room);
    if (s != GTET_OK) return s;
    size_t b2[256], e2[256];
    const int again =
        rebalance && (keys ? kpar_rebalance_cut(P, P->pk, pts, nth, end, stop_at, keys, sh, nmesh,
                                                b2, e2)
                           : kpar_rebalance_slabs(P, pts, nth, end, stop_at, nmesh,
                                                  (double *)(void *)P->tk, b2, e2));
    size_t n = 0;
    *attempts = 0;
    for (int k = 0; k < nth; k++) {
        memmove(pts + n, pts + begin[k], ndef[k] * sizeof *pts);
        n += ndef[k];
        *attempts += ntried[k];
        if (!again) {  /* a rest too short to cut: deferred, untried, no hint */
            for (size_t i = stop_at[k]; P->hint && i < end[k]; i++) P->hint[pts[i]] = UINT32_MAX;
            memmove(pts + n, pts + stop_at[k], (end[k] - stop_at[k]) * sizeof *pts);
            n += end[k] - stop_at[k];
        }
    }
    if (again) {
        for (int k = 0; k < nth; k++)
            if (end[k] - stop_at[k] >= KPAR_REBALANCE_MIN) *rebalanced += end[k] - stop_at[k];
        s = pass_region(P, P->ti, b2, e2, nth, 0, NULL, ndef, ntried, stop_at, &room);
        if (s != GTET_OK) return s;
        for (int k = 0; k < nth; k++) {
            memcpy(pts + n, P->ti + b2[k], ndef[k] * sizeof *pts);
            n += ndef[k];
            *attempts += ntried[k];
        }
    }
    *left = n;
    *out_of_room = room;
    return GTET_OK;
}

gtet_status kpar_round(kpar *P, uint32_t *pts, size_t np, gtet_round_stats *rs)
{
    kmesh *m = P->m;
    memset(rs, 0, sizeof *rs);
    rs->points = np;
    int nth = P->threads;
    if (nth > BASE_MAX_THREADS) nth = BASE_MAX_THREADS;
    unsigned pass = 0;
    size_t nmesh = 0;  /* after this round the mesh holds the vertices 0..nmesh-1 */
#pragma omp parallel for num_threads(nth) schedule(static) reduction(max : nmesh) \
    if (nth > 1 && np > 65536)
    for (size_t i = 0; i < np; i++)
        if (pts[i] >= nmesh) nmesh = (size_t)pts[i] + 1;
    if (np > P->cap_pending) {
        free(P->pk);
        free(P->tk);
        free(P->ti);
        P->pk = base_alloc_big(np * sizeof *P->pk);
        P->tk = base_alloc_big(np * sizeof *P->tk);
        P->ti = base_alloc_big(np * sizeof *P->ti);
        if (!P->pk || !P->tk || !P->ti) return GTET_ERR_OUT_OF_MEMORY;
        P->cap_pending = np;
    }
    while (np > 0) {
        while (nth > 1 && np < (size_t)nth * MIN_PER_THREAD) nth /= 2;
        if (pass > 1 && np < nmesh / SERIAL_TAIL) nth = 1;
        if (P->cancel && P->cancel(P->cancel_user)) return GTET_ERR_CANCELLED;
        rs->passes++;
        if (nth > rs->threads) rs->threads = nth;  /* the most threads any pass used */
        if (nth <= 1) {
            if (pass == 0) rs->alpha_first = 1.0;
            rs->tried += np;
            rs->inserted += np;
            return insert_serial(P, pts, np, pass > 0 && P->hint != NULL);
        }
        /* room for this pass: about 7 new tets per point, plus a block per thread */
        gtet_status s = km_reserve(m, m->nt + 8 * np + (size_t)nth * 2 * KM_SLOT_BLOCK);
        if (s == GTET_ERR_TOO_LARGE) s = km_reserve(m, KM_MAX_SLOTS);
        if (s != GTET_OK) return s;
        size_t left = 0;
        int out_of_room = 0;
        size_t attempts = 0;
        s = pass_parallel(P, pts, np, nmesh, nth, pass, &left, &attempts, &out_of_room,
                          &rs->rebalanced);
        if (s != GTET_OK) return s;
        size_t inserted = np - left;
        rs->ownership = P->own3 ? 3 : 4;
        P->done += inserted;
        if (P->progress) P->progress(P->progress_user, (double)P->done / (double)P->total);
        rs->tried += attempts;  /* points given up untried (GIVE_UP) are not attempts */
        rs->inserted += inserted;
        rs->deferred += attempts - inserted;
        double alpha = (double)inserted / (double)np;
        if (pass == 0) rs->alpha_first = alpha;
        np = left;
        pass++;
        if (out_of_room && inserted == 0 && m->cap >= KM_MAX_SLOTS) return GTET_ERR_TOO_LARGE;
        if (alpha <= 1.0 / nth && !P->own3) {
            /* the run's first failed pass: before the round goes to one thread, try
             * three-of-four ownership, which the rest of the run keeps (with all four, a vertex
             * in every tet -- the apex over a plane -- leaves only its own thread any work) */
            P->own3 = 1;
            continue;
        }
        if (alpha <= 1.0 / nth) nth = 1;           /* sequential */
        else if (alpha <= 1.0 / 6.0) nth /= 2;     /* reduction */
        /* else: box expansion, same threads, next pass */
    }
    return GTET_OK;
}
