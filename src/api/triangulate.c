/* triangulate.c -- gtet_triangulate: prepare -> build -> finish, and nothing else.
 *
 *   prepare: the arguments, then the validate stage: finite coordinates, exact duplicates
 *            (the result mesh gets its vertices and input map);
 *   build:   the sort stage (BRIO order and Moore keys), the validate stage's dimension test
 *            (the first tet), the kernel stage (kbuild_run: insertion and compaction);
 *   finish:  the phases' times, and the optional exact check (gtet_options.check) -- called
 *            from here: no stage calls a later one.
 * One cleanup path (release) frees what the run holds and, on failure, the mesh.  Messages
 * (gtet_options.verbosity, message) are formatted here and sent from the calling thread: one
 * line per phase at verbosity >= 1, one per BRIO round at >= 2 (the kernel reports its rounds
 * through kbuild_in.round_done, outside its parallel regions).  Nothing is printed.
 */
#include <omp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/base.h"
#include "../kernel/build.h"
#include "../kernel/kmesh.h"
#include "../mesh/mesh.h"
#include "../sort/sort.h"
#include "../validate/validate.h"
#include "memory.h"

#define BRIO_FIRST 2048
#define BRIO_RATIO 6.0
#define BRIO_SEED 0x67696761746574ULL  /* the result does not depend on it */

/* One call of gtet_triangulate. */
typedef struct run {
    const double *xyz;
    size_t n;
    gtet_options opts;
    gtet_error *err;
    int threads;
    gtet_mesh *res;
    uint32_t *order;       /* insertion order (mesh vertex ids) */
    uint64_t *keys;        /* the BRIO's keys, until the kernel takes them */
    int key_bits;
    size_t round_end[64];
    int num_rounds;
    double t_start, t_validated, t_sorted, t_inserted, t_done;
    mem_grow grow;         /* the memory guard's second check (memory.h) */
    int wide;              /* gtet_triangulate_wide (src/mesh/mesh.h) */
    int distinct;          /* gtet_triangulate_wide_distinct: no duplicate pass */
} run;

static void say(const run *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(const run *r, const char *fmt, ...)
{
    char line[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    r->opts.message(r->opts.message_user, line);
}

static int verbose(const run *r, int level)
{
    return r->opts.verbosity >= level && r->opts.message;
}

/* kbuild_in.round_done: one line per BRIO round at verbosity 2. */
static void say_round(void *user, int round, int num_rounds, const gtet_round_stats *rs,
                      double seconds)
{
    say(user,
        "round %d/%d: %llu points, %llu inserted in %d passes on %d threads "
        "(first pass alpha %.3f), %.3f s",
        round + 1, num_rounds, (unsigned long long)rs->points, (unsigned long long)rs->inserted,
        rs->passes, rs->threads, rs->alpha_first, seconds);
}

/* opts.input_done: the caller's xyz is no longer read (r->xyz is cleared so that no later
 * stage can read it by mistake). */
static void input_done(run *r)
{
    r->xyz = NULL;
    if (r->opts.input_done) r->opts.input_done(r->opts.input_done_user);
}

/* gtet_triangulate_wide_distinct: the caller's points are pairwise distinct, so the vertices
 * are the points in their order and the input map is the identity (what kval_dedup returns
 * for such points, without its hash pass). */
static gtet_status copy_distinct(run *r)
{
    gtet_mesh *res = r->res;
    const size_t n = r->n;
    res->vertices = base_alloc_big((n ? 3 * n : 3) * sizeof *res->vertices);
    res->input_map = base_alloc_big((n ? n : 1) * sizeof *res->input_map);
    if (!res->vertices || !res->input_map)
        return base_fail(r->err, GTET_ERR_OUT_OF_MEMORY, "allocating the vertices");
    if (n) memcpy(res->vertices, r->xyz, 3 * n * sizeof *res->vertices);
    for (size_t i = 0; i < n; i++) res->input_map[i] = (uint32_t)i;
    res->n_vertices = n;
    return GTET_OK;
}

/* The arguments, finite coordinates and duplicates: r->res holds the vertices. */
static gtet_status prepare(run *r, gtet_mesh **out)
{
    if (!out) return base_fail(r->err, GTET_ERR_ARGUMENT, "gtet_triangulate: mesh pointer is NULL");
    *out = NULL;
    if (!r->xyz && r->n)
        return base_fail(r->err, GTET_ERR_ARGUMENT, "gtet_triangulate: points are NULL");
    if (r->opts.threads < 0)
        return base_fail(r->err, GTET_ERR_ARGUMENT, "gtet_triangulate: negative thread count");
    if (r->n >= KM_MAX_VERTICES) {
        base_error(r->err, GTET_ERR_TOO_LARGE, SIZE_MAX, -1,
                   "%zu points exceed the 2^31-1 vertex limit", r->n);
        return GTET_ERR_TOO_LARGE;
    }
    r->t_start = omp_get_wtime();
    r->threads = r->opts.threads ? r->opts.threads : omp_get_max_threads();
    /* so do validate and sort (NOTES.md E159c: threads = 100000 was refused as needing 97.7 GiB
     * for 100 points, 5000 spawned 5000 threads in each OpenMP stage) */
    if (r->threads > BASE_MAX_THREADS) r->threads = BASE_MAX_THREADS;
    r->threads = base_team_size(r->threads);  /* what OpenMP will give (NOTES.md E184) */
    /* as many threads as the system lets the process start now: libgomp ends the process when
     * it cannot start a region's threads (ulimit -u, pids.max), and the tets do not depend on
     * the count (NOTES.md E183); stats.threads says how many ran */
    if (r->threads > 1) {
        int terr = 0, have = base_threads_available(r->threads, &terr);
        if (have < r->threads && verbose(r, 1))
            say(r, "threads: %d of the %d asked for can run (%s)", have, r->threads,
                strerror(terr));
        r->threads = have;
    }
    /* refuse a run that cannot fit before any big allocation (memory.c) */
    gtet_status s = mem_guard(r->n, r->threads, &r->opts, r->err);
    if (s != GTET_OK) return s;
    /* and which pages this run's big arrays ask for (hugepages.c base_page_run) */
    mem_estimate est;
    mem_estimate_run(r->n, r->threads, &r->opts, &est);
    base_page_run((size_t)est.resident);
    s = kval_finite(r->xyz, r->n, r->threads, r->err);
    if (s != GTET_OK) return s;
    r->res = calloc(1, sizeof *r->res);
    if (!r->res) return base_fail(r->err, GTET_ERR_OUT_OF_MEMORY, "allocating the result");
    gtet_mesh *res = r->res;
    res->n_points = r->n;
    s = r->distinct ? copy_distinct(r)
                    : kval_dedup(r->xyz, r->n, r->threads, &res->vertices, &res->input_map,
                                 &res->n_vertices, r->err);
    r->t_validated = omp_get_wtime();
    if (s == GTET_OK && !r->opts.check) input_done(r);
    if (s == GTET_OK && verbose(r, 1))
        say(r, "validate: %.3f s, %zu points, %zu duplicates", r->t_validated - r->t_start,
            r->n, r->n - res->n_vertices);
    return s;
}

/* The BRIO order; with threads, its Moore keys (21 bits per axis inside the cells it refined,
 * NOTES.md E257) also colour the vertices (kpar_init), unless one key holds more than a quarter
 * of a slice of some round (a point far away, a cluster below 2^-21 of the box): such keys
 * cannot cut the round evenly, and the kernel keys the tight box with 21 bits instead
 * (NOTES.md E7). */
static gtet_status order_points(run *r)
{
    const size_t nv = r->res->n_vertices;
    const int threads = r->threads;
    r->order = malloc((nv ? nv : 1) * sizeof *r->order);
    if (!r->order) return base_fail(r->err, GTET_ERR_OUT_OF_MEMORY, "allocating the insertion order");
    /* read at random when the kernel's tets are renamed to mesh ids (build.c kbuild_finish):
     * 4 B per tet vertex from an array of 4 B per point (NOTES.md E19) */
    base_hugepages(r->order, nv * sizeof *r->order);
    uint32_t *order = r->order;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nv > 65536)
    for (size_t i = 0; i < nv; i++) order[i] = (uint32_t)i;
    double crowd = 0.0;
    gtet_status s = sort_brio_keys(r->res->vertices, 3, order, nv, BRIO_SEED, BRIO_FIRST,
                                   BRIO_RATIO, r->round_end, &r->num_rounds, threads,
                                   threads > 1 ? &r->keys : NULL, &r->key_bits, NULL, &crowd);
    if (crowd > 0.25 / threads) {
        free(r->keys);
        r->keys = NULL;
    }
    r->t_sorted = omp_get_wtime();
    if (s != GTET_OK) return base_fail(r->err, s, "sorting the points");
    if (verbose(r, 1))
        say(r, "sort: %.3f s, %d BRIO rounds", r->t_sorted - r->t_validated, r->num_rounds);
    return GTET_OK;
}

/* Sort, first tet, kernel. */
static gtet_status build(run *r)
{
    gtet_status s = order_points(r);
    if (s != GTET_OK) return s;
    gtet_mesh *res = r->res;
    kbuild_in in;
    memset(&in, 0, sizeof in);
    /* its counts open the run's predicate counters (res->stats.pred) */
    s = kval_first_simplex(res->vertices, r->order, res->n_vertices, in.first, &res->stats.pred,
                           r->err);
    if (s != GTET_OK) return s;
    in.order = r->order;
    in.round_end = r->round_end;
    in.num_rounds = r->num_rounds;
    in.keys = r->keys;
    in.key_bits = r->key_bits;
    r->keys = NULL;  /* kbuild_run frees them */
    in.threads = r->threads;
    in.degeneracies = r->opts.degeneracies;
    in.degeneracy_limit = r->opts.degeneracy_limit;
    in.progress = r->opts.progress;
    in.progress_user = r->opts.progress_user;
    in.cancel = r->opts.cancel;
    in.cancel_user = r->opts.cancel_user;
    in.wide = r->wide;
    if (r->opts.memory_limit == 0) {  /* the guard's default mode: checked again on growth */
        r->grow = (mem_grow){res->n_vertices, r->err, "/proc", "/sys"};
        in.grow_guard = mem_grow_guard;
        in.grow_user = &r->grow;
    }
    if (verbose(r, 2)) {
        in.round_done = say_round;
        in.round_user = r;
    }
    s = kbuild_run(&in, res, &r->t_inserted, r->err);
    free(r->order);
    r->order = NULL;
    if (s != GTET_OK) return base_fail(r->err, s, "inserting the points");
    r->t_done = omp_get_wtime();
    if (verbose(r, 1)) {
        say(r, "insert: %.3f s, %llu tets created", r->t_inserted - r->t_sorted,
            (unsigned long long)res->stats.tets_created);
        say(r, "finalize: %.3f s, %zu tets, %zu hull facets", r->t_done - r->t_inserted,
            res->n_tets, res->n_hull_facets);
    }
    return GTET_OK;
}

/* Times, then the optional check. */
static gtet_status finish(run *r)
{
    gtet_stats *st = &r->res->stats;
    st->seconds_validate = r->t_validated - r->t_start;
    st->seconds_sort = r->t_sorted - r->t_validated;
    st->seconds_insert = r->t_inserted - r->t_sorted;
    st->seconds_finalize = r->t_done - r->t_inserted;
    st->seconds_total = r->t_done - r->t_start;
    if (!r->opts.check) return GTET_OK;
    gtet_check_report rep;
    gtet_check_options co;  /* the run's cancel hook reaches into the check */
    gtet_check_options_init(&co);
    co.cancel = r->opts.cancel;
    co.cancel_user = r->opts.cancel_user;
    const gtet_status s = gtet_check_opt(r->res, r->xyz, r->n, &co, &rep);
    if (s != GTET_OK) base_error(r->err, s, SIZE_MAX, -1, "%s", rep.message);
    else input_done(r);
    if (verbose(r, 1)) say(r, "check: %s", s == GTET_OK ? "ok" : rep.message);
    return s;
}

static gtet_status triangulate(const double *xyz, size_t n, const gtet_options *opts_in,
                               int wide, int distinct, gtet_mesh **out)
{
    run r;
    memset(&r, 0, sizeof r);
    r.wide = wide;
    r.distinct = distinct;
    r.xyz = xyz;
    r.n = n;
    if (opts_in) r.opts = *opts_in;
    else gtet_options_init(&r.opts);
    r.err = r.opts.error;
    if (r.err) {
        memset(r.err, 0, sizeof *r.err);
        r.err->index = SIZE_MAX;
        r.err->dimension = -1;
    }
    /* with dyn-var on (OMP_DYNAMIC, omp_set_dynamic) OpenMP may give a region fewer threads
     * than num_threads asks, and the stages split their work by thread number: a validate
     * region of 1 thread for 2 asked left half the points unread and crashed (NOTES.md
     * E184).  Off for the call (this thread's setting: the regions it starts inherit it),
     * then as the caller had it. */
    const int dynamic = omp_get_dynamic();
    if (dynamic) omp_set_dynamic(0);
    gtet_status s = prepare(&r, out);
    if (s == GTET_OK) s = build(&r);
    if (s == GTET_OK) s = finish(&r);
    if (dynamic) omp_set_dynamic(1);
    /* release: one path for success and every failure */
    free(r.keys);
    free(r.order);
    if (s != GTET_OK) {
        gtet_mesh_free(&r.res);
        return s;
    }
    *out = r.res;
    return GTET_OK;
}

gtet_status gtet_triangulate(const double *xyz, size_t n, const gtet_options *opts_in,
                             gtet_mesh **out)
{
    return triangulate(xyz, n, opts_in, 0, 0, out);
}

gtet_status gtet_triangulate_wide(const double *xyz, size_t n, const gtet_options *opts_in,
                                  gtet_mesh **out)
{
    return triangulate(xyz, n, opts_in, 1, 0, out);
}

gtet_status gtet_triangulate_wide_distinct(const double *xyz, size_t n,
                                           const gtet_options *opts_in, gtet_mesh **out)
{
    return triangulate(xyz, n, opts_in, 1, 1, out);
}
