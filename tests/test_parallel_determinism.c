/* test_parallel_determinism.c -- the parallel kernel's output does not depend on the thread
 * count nor on the input order (issue 4, "Evidence it is right").
 *
 * gigatet's output is THE perturbed Delaunay tetrahedrization of the distinct input points
 * (gigatet.h; proofs/perturbation.md: unique under the lexicographic symbolic perturbation),
 * so every run must produce the same set of tets.  For each point set this test triangulates
 * with threads = 1, 2, 3, 4 and 8 and a shuffled copy with threads = 4, maps every tet to the
 * input indices of its vertices (the smallest original index among the input points that map
 * to a vertex), sorts each tet's four indices and then the list, and requires identical
 * lists.  The 4-thread result passes the exact checker (gtet_check; every other run has the
 * same tets, so one check covers them all), and the per-round statistics
 * (gtet_mesh_stats -> rounds[k].threads) must show that a round really ran on more than one
 * thread -- the kernel only splits a round with >= 2048 points per thread (src/kernel/
 * parallel.c), hence the sizes: 200k random points, a 30^3 integer grid (every insphere of a
 * cube is exactly 0: the perturbation decides) and ~14k integer points of one sphere.
 * Under a sanitizer (ASan / TSan, several times slower) the sets are 10k-40k points, still
 * enough for 2-4 threads per round.
 */
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include "gigatet.h"
#include "io/io.h"
#include "canon.h"
#include "testutil.h"

#ifdef GTET_TEST_SANITIZED
enum { N_RANDOM = 40000, GRID_K = 24, SPHERE_M = 3003 };
static const int THREADS[] = {1, 2, 3, 4};
#else
enum { N_RANDOM = 200000, GRID_K = 30, SPHERE_M = 4641 };
static const int THREADS[] = {1, 2, 3, 4, 8};
#endif
#define NTHREADS (sizeof THREADS / sizeof *THREADS)

/* ---- point sets -------------------------------------------------------------------------- */

static double *uniform(size_t n, uint64_t seed)
{
    tu_rng r = {seed};
    double *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; p && i < 3 * n; i++) p[i] = tu_uniform(&r);
    return p;
}

static double *grid(int k, size_t *n)
{
    *n = (size_t)k * k * k;
    double *p = malloc(3 * *n * sizeof *p), *q = p;
    for (int x = 0; p && x < k; x++)
        for (int y = 0; y < k; y++)
            for (int z = 0; z < k; z++) {
                *q++ = x;
                *q++ = y;
                *q++ = z;
            }
    return p;
}

static int cmp_xyz(const void *a, const void *b)
{
    const double *p = a, *q = b;
    for (int i = 0; i < 3; i++)
        if (p[i] != q[i]) return p[i] < q[i] ? -1 : 1;
    return 0;
}

/* Integer points of the sphere of radius m centred at 0, from Euler's parametrisation of
 * the quaternions q = (a,b,c,d) with a^2+b^2+c^2+d^2 = m: the point
 * (a^2+b^2-c^2-d^2, 2(ad+bc), 2(bd-ac)) has norm m exactly (all values < 2^53: exact).
 * Duplicates (q and -q give the same point) are removed. */
static double *cospherical(int m, size_t *n)
{
    size_t cap = 1024, k = 0;
    double *p = malloc(3 * cap * sizeof *p);
    int r = 0;
    while ((r + 1) * (r + 1) <= m) r++;
    for (int a = -r; p && a <= r; a++)
        for (int b = -r; b <= r; b++) {
            int ab = a * a + b * b;
            if (ab > m) continue;
            for (int c = -r; c <= r; c++) {
                int rest = m - ab - c * c;
                if (rest < 0) continue;
                int d = 0;
                while ((d + 1) * (d + 1) <= rest) d++;
                if (d * d != rest) continue;
                for (int sd = -1; sd <= 1; sd += 2) {
                    if (d == 0 && sd > 0) continue;
                    int dd = sd * d;
                    if (k == cap) {
                        double *np = realloc(p, 3 * (cap *= 2) * sizeof *p);
                        if (!np) {
                            free(p);
                            return NULL;
                        }
                        p = np;
                    }
                    p[3 * k] = (double)a * a + (double)b * b - (double)c * c - (double)dd * dd;
                    p[3 * k + 1] = 2.0 * ((double)a * dd + (double)b * c);
                    p[3 * k + 2] = 2.0 * ((double)b * dd - (double)a * c);
                    k++;
                }
            }
        }
    if (!p) return NULL;
    qsort(p, k, 3 * sizeof *p, cmp_xyz);
    size_t w = 0;
    for (size_t i = 0; i < k; i++)
        if (w == 0 || cmp_xyz(p + 3 * (w - 1), p + 3 * i) != 0) memmove(p + 3 * w++, p + 3 * i, 3 * sizeof *p);
    /* a reproducible shuffle: the input order should not be the sorted one */
    tu_rng rng = {4242};
    for (size_t i = w; i > 1; i--) {
        size_t j = tu_below(&rng, i);
        double t[3];
        memcpy(t, p + 3 * (i - 1), sizeof t);
        memcpy(p + 3 * (i - 1), p + 3 * j, sizeof t);
        memcpy(p + 3 * j, t, sizeof t);
    }
    *n = w;
    return p;
}

/* Triangulate p with `threads`, check exactly, return the canonical list (and its length);
 * *max_threads = the most threads any round used. */
static uint32_t *run(const char *name, const double *p, size_t n, const uint32_t *orig,
                     int threads, int check, size_t *nt, int *max_threads)
{
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.threads = threads;
    o.error = &err;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(p, n, &o, &m);
    if (s != GTET_OK) {
        tu_fail(__FILE__, __LINE__, "%s, %d threads: status %d: %s", name, threads, (int)s,
                err.message);
        return NULL;
    }
    if (check) {
        gtet_check_report rep;
        s = gtet_check(m, p, n, 0, &rep);
        TEST_CHECK(s == GTET_OK && rep.ok, "%s, %d threads: check failed: %s", name, threads,
                   rep.message);
    }
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    *max_threads = 1;
    for (int k = 0; k < st.num_rounds; k++) {
        const gtet_round_stats *r = &st.rounds[k];
        TEST_CHECK(r->inserted <= r->points && r->tried >= r->inserted,
                   "%s, %d threads, round %d: inconsistent counters", name, threads, k);
        TEST_CHECK(r->threads >= 1 && r->threads <= threads,
                   "%s: round %d used %d threads of %d", name, k, r->threads, threads);
        /* rounds[k].threads is the thread count of the round's last pass; a round that needed
         * several passes ran its earlier ones in parallel (a sequential pass is always the
         * last: it inserts every pending point) */
        int used = r->passes > 1 && r->threads < 2 ? 2 : r->threads;
        if (used > *max_threads) *max_threads = used;
    }
    *nt = gtet_mesh_num_tets(m);
    char why[160];
    uint32_t *c = canon_input_ids(m, orig, n, why);
    gtet_mesh_free(&m);
    TEST_CHECK(c != NULL, "%s: %s", name, why);
    return c;
}

static void same_tets_for_every_thread_count_and_order(const char *name, const double *p,
                                                       size_t n)
{
    size_t nt1 = 0;
    int mt = 0;
    uint32_t *ref = run(name, p, n, NULL, 1, 0, &nt1, &mt);
    if (!ref) return;
    TEST_CHECK(nt1 > n, "%s: only %zu tets for %zu points", name, nt1, n);
    for (size_t k = 1; k < NTHREADS; k++) {
        size_t nt = 0;
        uint32_t *c = run(name, p, n, NULL, THREADS[k], THREADS[k] == 4, &nt, &mt);
        if (!c) continue;
        TEST_CHECK(nt == nt1 && memcmp(c, ref, 4 * nt * sizeof *c) == 0,
                   "%s: %d threads give other tets (%zu vs %zu)", name, THREADS[k], nt, nt1);
        TEST_CHECK(mt >= 2, "%s: %d threads requested, but no round ran on more than one",
                   name, THREADS[k]);
        free(c);
    }
    /* shuffled input, 4 threads */
    double *q = malloc(3 * n * sizeof *q);
    uint32_t *orig = malloc(n * sizeof *orig);
    if (q && orig) {
        for (size_t i = 0; i < n; i++) orig[i] = (uint32_t)i;
        tu_rng r = {99};
        for (size_t i = n; i > 1; i--) {
            size_t j = tu_below(&r, i);
            uint32_t t = orig[i - 1];
            orig[i - 1] = orig[j];
            orig[j] = t;
        }
        for (size_t i = 0; i < n; i++) memcpy(q + 3 * i, p + 3 * (size_t)orig[i], 3 * sizeof *q);
        size_t nt = 0;
        uint32_t *c = run(name, q, n, orig, 4, 0, &nt, &mt);
        if (c) {
            TEST_CHECK(nt == nt1 && memcmp(c, ref, 4 * nt * sizeof *c) == 0,
                       "%s: shuffled input gives other tets (%zu vs %zu)", name, nt, nt1);
            TEST_CHECK(mt >= 2, "%s shuffled: no round ran on more than one thread", name);
        }
        free(c);
    }
    free(q);
    free(orig);
    free(ref);
}

/* ---- tests -------------------------------------------------------------------------------- */

static void test_random_points_give_the_same_tets_for_1_2_3_4_8_threads_and_shuffled(void)
{
    double *p = uniform(N_RANDOM, 2024);
    TEST_REQUIRE(p != NULL, "out of memory");
    same_tets_for_every_thread_count_and_order("uniform", p, N_RANDOM);
    free(p);
}

static void test_integer_grid_every_insphere_degenerate_gives_the_same_tets_in_parallel(void)
{
    size_t n;
    double *p = grid(GRID_K, &n);
    TEST_REQUIRE(p != NULL, "out of memory");
    same_tets_for_every_thread_count_and_order("grid", p, n);
    free(p);
}

static void test_cospherical_integer_points_give_the_same_tets_in_parallel(void)
{
    size_t n = 0;
    double *p = cospherical(SPHERE_M, &n);
    TEST_REQUIRE(p != NULL, "out of memory");
    TEST_REQUIRE(n >= 8192, "only %zu co-spherical points: too few for parallel rounds", n);
    same_tets_for_every_thread_count_and_order("cospherical", p, n);
    free(p);
}

/* Points on the unit sphere (rounded, so not exactly co-spherical): every point is on the
 * hull when inserted and every cavity reaches ghosts.  A walk from a ghost that skipped the
 * hull facet made parallel passes fail with "internal error" on such sets, but only for some
 * seeds and thread counts (1 of 20 runs of 100k points); tests/test_kernel_walk.c is the
 * deterministic minimal case, this is the hull-heavy family in the determinism oracle. */
static void test_points_on_a_sphere_all_on_the_hull_give_the_same_tets_in_parallel(void)
{
    const size_t n = N_RANDOM / 2;
    double *p = uniform(n, 4242);
    TEST_REQUIRE(p != NULL, "out of memory");
    for (size_t i = 0; i < n; i++) {
        double *q = p + 3 * i, r2 = 0;
        for (int j = 0; j < 3; j++) {
            q[j] = 2 * q[j] - 1;
            r2 += q[j] * q[j];
        }
        const double r = sqrt(r2 > 0 ? r2 : 1);
        for (int j = 0; j < 3; j++) q[j] /= r;
    }
    same_tets_for_every_thread_count_and_order("sphere surface", p, n);
    free(p);
}

/* Half the points in a cube of side 1e-9: far below one Moore cell (2^-21 of the box), so
 * tens of thousands of pending points share one key; slices are never cut between equal keys,
 * so some slices come out empty or tiny, and the colour boundaries must still give every
 * point its own slice's colour (proofs/parallel.md O1). */
static void test_points_sharing_one_moore_key_give_the_same_tets_in_parallel(void)
{
    const size_t half = N_RANDOM / 4;
    double *p = uniform(2 * half, 77);
    TEST_REQUIRE(p != NULL, "out of memory");
    for (size_t i = half; i < 2 * half; i++)
        for (int j = 0; j < 3; j++) p[3 * i + (size_t)j] = 0.5 + 1e-9 * p[3 * i + (size_t)j];
    same_tets_for_every_thread_count_and_order("one-key cluster", p, 2 * half);
    free(p);
}

/* Duplicates on every thread count (src/validate/validate.c: a serial pass below 2^17 points,
 * a parallel table of first occurrences above): 3000 distinct points of a small lattice with
 * zero coordinates, each copied about 60 times in random order, some zeros written as -0.0
 * (equal to +0.0, so duplicates).  The vertices (bit for bit: the first occurrence's sign of
 * zero) and the input map must be the same for 1..8 threads; vertex ids must follow the order
 * of first occurrence, and every point must map to a vertex that compares equal to it. */
static void test_duplicates_are_mapped_the_same_way_for_every_thread_count(void)
{
    const size_t nd = 3000, n = 180000;  /* n/2 >= 2^16: the parallel dedup runs on 2 threads */
    tu_rng r = {31337};
    double *d = malloc(3 * nd * sizeof *d), *p = malloc(3 * n * sizeof *p);
    TEST_REQUIRE(d && p, "out of memory");
    for (size_t i = 0; i < 3 * nd; i++) d[i] = (double)tu_below(&r, 40) - 20;
    for (size_t i = 0; i < n; i++) {
        const size_t k = i < nd ? i * 7919 % nd : tu_below(&r, nd);  /* every one at least once */
        for (int j = 0; j < 3; j++) {
            double x = d[3 * k + (size_t)j];
            if (x == 0 && tu_below(&r, 2)) x = -0.0;
            p[3 * i + (size_t)j] = x;
        }
    }
    double *v1 = NULL;
    uint32_t *m1 = NULL;
    size_t nv1 = 0;
    for (size_t k = 0; k < NTHREADS; k++) {
        gtet_options o;
        gtet_options_init(&o);
        o.threads = THREADS[k];
        gtet_mesh *m = NULL;
        const gtet_status st = gtet_triangulate(p, n, &o, &m);
        TEST_CHECK(st == GTET_OK, "%d threads: %s", THREADS[k], gtet_status_str(st));
        if (st != GTET_OK) continue;
        const size_t nv = gtet_mesh_num_vertices(m);
        const double *v = gtet_mesh_vertices(m);
        const uint32_t *map = gtet_mesh_input_map(m);
        if (!v1) {
            /* the reference: properties, then every other count must equal it */
            uint32_t next = 0;
            long bad = 0;
            for (size_t i = 0; i < n; i++) {
                const double *q = v + 3 * (size_t)map[i];
                bad += map[i] > next || !(q[0] == p[3 * i] && q[1] == p[3 * i + 1] &&
                                         q[2] == p[3 * i + 2]);
                if (map[i] == next) {
                    bad += memcmp(q, p + 3 * i, 3 * sizeof *q) != 0;  /* first occurrence */
                    next++;
                }
            }
            TEST_CHECK(bad == 0 && next == nv, "%ld bad map entries, %u ids for %zu vertices",
                       bad, next, nv);
            TEST_CHECK(nv <= nd && nv > nd / 2, "%zu distinct of %zu", nv, nd);
            nv1 = nv;
            v1 = malloc(3 * nv * sizeof *v1);
            m1 = malloc(n * sizeof *m1);
            TEST_REQUIRE(v1 && m1, "out of memory");
            memcpy(v1, v, 3 * nv * sizeof *v1);
            memcpy(m1, map, n * sizeof *m1);
        } else {
            TEST_CHECK(nv == nv1 && memcmp(v, v1, 3 * nv * sizeof *v) == 0 &&
                           memcmp(map, m1, n * sizeof *map) == 0,
                       "%d threads: other vertices or map than 1 thread", THREADS[k]);
        }
        gtet_mesh_free(&m);
    }
    free(v1);
    free(m1);
    free(d);
    free(p);
}

/* The mesh of p with two threads and its statistics (NULL on failure). */
static gtet_mesh *with_two_threads(const double *p, size_t n, gtet_stats *st)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 2;
    gtet_mesh *m = NULL;
    if (gtet_triangulate(p, n, &o, &m) != GTET_OK) return NULL;
    gtet_mesh_stats(m, st);
    return m;
}

/* Points on the plane z = 0 and one apex above it: every tet has the apex, which has one
 * colour.  Ownership by all four vertices lets only the apex's thread insert: a first pass
 * inserts about half its points with 2 threads and the rest would go serial.  So the run's
 * first failed pass switches to three-of-four ownership (kpar_round, km_owned), with which
 * the other threads insert too.  Specification: the same tets for every thread count and order; with
 * 2 threads the last round's first pass inserts at least 3/4 of its points, and an earlier
 * round went on in parallel after its failed first pass (passes > 2 or alpha > 1/2). */
static void test_a_vertex_in_every_tet_does_not_stop_the_other_threads(void)
{
    const size_t n = N_RANDOM / 2;
    double *p = uniform(n, 777);
    TEST_REQUIRE(p != NULL, "out of memory");
    for (size_t i = 0; i < n; i++) p[3 * i + 2] = 0;
    p[2] = 1.0;  /* the apex */
    same_tets_for_every_thread_count_and_order("plane + apex", p, n);
    gtet_stats st;
    gtet_mesh *m = with_two_threads(p, n, &st);
    TEST_REQUIRE(m != NULL, "plane + apex fails");
    TEST_REQUIRE(st.num_rounds >= 2, "%d rounds", st.num_rounds);
    const gtet_round_stats *last = &st.rounds[st.num_rounds - 1];
    TEST_CHECK(last->ownership == 3, "the last round's passes used ownership %d, not 3",
               last->ownership);
    int switched_before = 0;
    for (int r = 0; r + 1 < st.num_rounds; r++) switched_before |= st.rounds[r].ownership == 3;
    if (switched_before)  /* the last round ran all its passes with three-of-four */
        TEST_CHECK(last->alpha_first >= 0.75,
                   "last round (%llu points): the first pass inserted only %.3f of them",
                   (unsigned long long)last->points, last->alpha_first);
    gtet_mesh_free(&m);
    free(p);
}

/* Half the points uniform in the unit cube, half in the cube [0.5, 0.5 + 10^-3)^3, which lies
 * inside one Delaunay cell of the sparse half.  With 2 threads the last round's slice boundary
 * crosses the small cube, and each thread's slice starts far from where its last insertion
 * ended: a walk from there left the thread's colour, deferred the point and, starting again
 * from the same tet, every next one, until the thread gave up on its slice (this set: the
 * last round's first pass inserted 0.424 of its points in three runs of three; the start
 * tets are now located by walking to the slice's first points before the pass: find_start
 * in parallel.c).  The equal-count cut still ran through the small cube (0.735); the cuts now
 * lie on Moore-cell boundaries with a free origin, and the small cube is one slice (0.971:
 * cut_on_cells in parallel.c, NOTES.md E12).  The first pass's rebalancing (E186) cuts the
 * rest of the slower thread's slice once more, and that cut defers a few percent more,
 * depending on when the other thread finished (0.895 in one loaded run).  Specification: the
 * same tets for every thread count and order; with 2 threads the last round's first pass
 * inserts more than 0.85 of its points (the failures above: 0.424, 0.735).  The
 * sanitized builds, at 40k points, check the tets only (a smaller set did not show the
 * failure every time: 100k points, 0.33 in one run of five). */
static void test_a_dense_cluster_inside_one_cell_keeps_both_threads_inserting(void)
{
    const size_t n = N_RANDOM;
    double *p = uniform(n, 4242);
    TEST_REQUIRE(p != NULL, "out of memory");
    for (size_t i = n / 2; i < n; i++)
        for (int d = 0; d < 3; d++) p[3 * i + (size_t)d] = 0.5 + 1e-3 * p[3 * i + (size_t)d];
    same_tets_for_every_thread_count_and_order("uniform + dense cube", p, n);
#ifndef GTET_TEST_SANITIZED
    gtet_stats st;
    gtet_mesh *m = with_two_threads(p, n, &st);
    TEST_REQUIRE(m != NULL, "uniform + dense cube fails");
    const gtet_round_stats *last = &st.rounds[st.num_rounds - 1];
    TEST_CHECK(last->threads == 2 && last->alpha_first > 0.85,
               "last round (%llu points, %d threads): the first pass inserted %.3f of them",
               (unsigned long long)last->points, last->threads, last->alpha_first);
    gtet_mesh_free(&m);
#endif
    free(p);
}

/* Points on a paraboloid (`gigatet generate paraboloid`): the cavities reach across the whole
 * set, no parallel insertion succeeds (alpha about 0.001) and the round goes serial; walking
 * and rolling back every point in a doomed parallel pass first would make -t 2 slower than
 * -t 1.  Specification: the same tets for every thread count,
 * and with 2 threads a round tries each point at most once plus what the probes of the first
 * pass cost (GIVE_UP in parallel.c: max(1024, slice / 16) per thread) -- except the one round
 * where the run switches to three-of-four ownership and tries a second parallel pass
 * (kpar_round; the first round whose ownership is 3). */
static void test_a_pass_where_every_point_fails_gives_up_early(void)
{
    double *p = NULL;
    size_t n = 0;
    io_error ie;
    TEST_REQUIRE(io_generate("paraboloid", N_RANDOM / 4, 1, &p, &n, &ie) == IO_OK, "generator");
    same_tets_for_every_thread_count_and_order("paraboloid", p, n);
    gtet_stats st;
    gtet_mesh *m = with_two_threads(p, n, &st);
    TEST_REQUIRE(m != NULL, "paraboloid fails");
    int over = 0, first3 = -1;
    for (int r = 0; r < st.num_rounds; r++) {
        const gtet_round_stats *rs = &st.rounds[r];
        if (first3 < 0 && rs->ownership == 3) first3 = r;
        const double bound = (double)rs->points * (1.0 + 2.0 / 32) + 2 * 1024 + 2;
        if ((double)rs->tried <= bound) continue;
        over++;
        TEST_CHECK(over == 1 && r == first3,
                   "round %d: %llu tries for %llu points (alpha of the first pass %.3f)", r,
                   (unsigned long long)rs->tried, (unsigned long long)rs->points,
                   rs->alpha_first);
    }
    gtet_mesh_free(&m);
    free(p);
}

int main(void)
{
    TU_RUN(test_random_points_give_the_same_tets_for_1_2_3_4_8_threads_and_shuffled);
    TU_RUN(test_integer_grid_every_insphere_degenerate_gives_the_same_tets_in_parallel);
    TU_RUN(test_cospherical_integer_points_give_the_same_tets_in_parallel);
    TU_RUN(test_points_sharing_one_moore_key_give_the_same_tets_in_parallel);
    TU_RUN(test_points_on_a_sphere_all_on_the_hull_give_the_same_tets_in_parallel);
    TU_RUN(test_duplicates_are_mapped_the_same_way_for_every_thread_count);
    TU_RUN(test_a_vertex_in_every_tet_does_not_stop_the_other_threads);
    TU_RUN(test_a_pass_where_every_point_fails_gives_up_early);
    TU_RUN(test_a_dense_cluster_inside_one_cell_keeps_both_threads_inserting);
    return tu_finish();
}
