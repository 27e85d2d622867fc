/* test_kernel_triangulate.c -- gtet_triangulate on random and degenerate point sets: every
 * result passes the exact checker (an independent GMP implementation), the tet set does not
 * depend on the input order, duplicates are mapped, and degenerate input is reported with its
 * dimension.  Exercises proofs/perturbation.md (uniqueness: same tets for a shuffled input)
 * and proofs/termination.md (every family terminates, grids included). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gigatet.h"
#include "canon.h"
#include "testutil.h"

/* Sanitized builds (GTET_TEST_SMALL) divide the big sets by 8: same families, same checks. */
#ifdef GTET_TEST_SMALL
#define BIG(n) ((n) / 8)
#else
#define BIG(n) (n)
#endif

/* ---- point sets -------------------------------------------------------------------------- */

static double *uniform(size_t n, uint64_t seed)
{
    tu_rng r = {seed};
    double *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < 3 * n; i++) p[i] = tu_uniform(&r);
    return p;
}

static double *grid(int k, size_t *n)
{
    *n = (size_t)k * k * k;
    double *p = malloc(3 * *n * sizeof *p), *q = p;
    for (int x = 0; x < k; x++)
        for (int y = 0; y < k; y++)
            for (int z = 0; z < k; z++) {
                *q++ = x;
                *q++ = y;
                *q++ = z;
            }
    return p;
}

/* integer points on the sphere x^2+y^2+z^2 = r2 */
static double *cospherical(int r2, size_t *n)
{
    int r = (int)sqrt((double)r2) + 1;
    size_t cap = 64, m = 0;
    double *p = malloc(3 * cap * sizeof *p);
    for (int x = -r; x <= r; x++)
        for (int y = -r; y <= r; y++)
            for (int z = -r; z <= r; z++) {
                if (x * x + y * y + z * z != r2) continue;
                if (m == cap) p = realloc(p, 3 * (cap *= 2) * sizeof *p);
                p[3 * m] = x;
                p[3 * m + 1] = y;
                p[3 * m + 2] = z;
                m++;
            }
    *n = m;
    return p;
}

static void shuffle(double *p, size_t n, uint64_t seed)
{
    tu_rng r = {seed};
    for (size_t i = n; i > 1; i--) {
        size_t j = tu_below(&r, i);
        for (int d = 0; d < 3; d++) {
            double t = p[3 * (i - 1) + d];
            p[3 * (i - 1) + d] = p[3 * j + d];
            p[3 * j + d] = t;
        }
    }
}

/* Triangulate, check exactly, and compare with a shuffled copy. */
static void check_set(const char *name, double *p, size_t n, int threads)
{
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.threads = threads;
    o.error = &err;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(p, n, &o, &m);
    TEST_REQUIRE(s == GTET_OK, "%s (n=%zu): status %d: %s", name, n, s, err.message);
    gtet_check_report rep;
    s = gtet_check(m, p, n, n <= 300 ? GTET_CHECK_FULL : 0, &rep);
    TEST_CHECK(s == GTET_OK && rep.ok, "%s (n=%zu): check failed: %s", name, n, rep.message);
    TEST_CHECK(gtet_mesh_num_tets(m) > 0, "%s: no tets", name);

    double *q = malloc(3 * n * sizeof *q);
    memcpy(q, p, 3 * n * sizeof *q);
    shuffle(q, n, 77);
    gtet_mesh *m2 = NULL;
    s = gtet_triangulate(q, n, &o, &m2);
    TEST_REQUIRE(s == GTET_OK, "%s shuffled: status %d", name, s);
    size_t nt = gtet_mesh_num_tets(m);
    TEST_CHECK(nt == gtet_mesh_num_tets(m2), "%s: %zu tets, %zu when shuffled", name, nt,
               gtet_mesh_num_tets(m2));
    if (nt == gtet_mesh_num_tets(m2)) {
        canon_tet *a = canon_coords(m), *b = canon_coords(m2);
        TEST_CHECK(a && b && memcmp(a, b, nt * sizeof *a) == 0,
                   "%s: shuffled input gives other tets", name);
        free(a);
        free(b);
    }
    gtet_mesh_free(&m);
    gtet_mesh_free(&m2);
    free(q);
}

/* ---- tests -------------------------------------------------------------------------------- */

/* Exercises proofs/perturbation.md P4, proofs/termination.md T1. */
static void test_random_sets_of_many_sizes_pass_the_exact_checker(void)
{
    const size_t sizes[] = {4, 5, 6, 7, 10, 20, 50, 100, 300, 1000, 5000, BIG(30000)};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        double *p = uniform(sizes[i], 1000 + i);
        check_set("uniform", p, sizes[i], 1);
        free(p);
    }
}

/* Exercises proofs/perturbation.md P3, proofs/termination.md T1. */
static void test_integer_grids_every_insphere_degenerate_are_perturbed_consistently(void)
{
    for (int k = 2; k <= 12; k += (k < 5 ? 1 : 7)) {
        size_t n;
        double *p = grid(k, &n);
        check_set("grid", p, n, 1);
        free(p);
    }
}

/* Exercises proofs/perturbation.md P4, proofs/termination.md T2. */
static void test_cospherical_integer_points_are_triangulated_uniquely(void)
{
    const int r2s[] = {3, 9, 25, 50, 101, 325};
    for (size_t i = 0; i < sizeof r2s / sizeof *r2s; i++) {
        size_t n;
        double *p = cospherical(r2s[i], &n);
        if (n >= 4) check_set("cospherical", p, n, 1);
        free(p);
    }
}

/* Exercises proofs/perturbation.md P4, proofs/termination.md T2. */
static void test_cube_corners_and_centre(void)
{
    double p[27];
    for (int i = 0; i < 8; i++) {
        p[3 * i] = i & 1;
        p[3 * i + 1] = (i >> 1) & 1;
        p[3 * i + 2] = (i >> 2) & 1;
    }
    check_set("cube corners", p, 8, 1);
    p[24] = p[25] = p[26] = 0.5;
    check_set("cube corners + centre", p, 9, 1);
}

/* Exercises proofs/perturbation.md P6 (hull faces in any order). */
static void test_lattices_paraboloid_and_plane_with_denormal_apex(void)
{
    size_t n = 0;
    double *p = malloc(3 * 4000 * sizeof *p);
    /* FCC: cube corners + face centres of a 6^3 block, doubled to stay integer */
    for (int x = 0; x < 7; x++)
        for (int y = 0; y < 7; y++)
            for (int z = 0; z < 7; z++)
                if ((x + y + z) % 2 == 0) {
                    p[3 * n] = x;
                    p[3 * n + 1] = y;
                    p[3 * n + 2] = z;
                    n++;
                }
    check_set("fcc", p, n, 1);
    /* BCC: a grid plus the cube centres */
    n = 0;
    for (int x = 0; x < 6; x++)
        for (int y = 0; y < 6; y++)
            for (int z = 0; z < 6; z++) {
                p[3 * n] = 2 * x;
                p[3 * n + 1] = 2 * y;
                p[3 * n + 2] = 2 * z;
                n++;
                if (x < 5 && y < 5 && z < 5) {
                    p[3 * n] = 2 * x + 1;
                    p[3 * n + 1] = 2 * y + 1;
                    p[3 * n + 2] = 2 * z + 1;
                    n++;
                }
            }
    check_set("bcc", p, n, 1);
    /* paraboloid lift of an integer grid: all points co-spherical in 4-tuples */
    n = 0;
    for (int x = -6; x <= 6; x++)
        for (int y = -6; y <= 6; y++) {
            p[3 * n] = x;
            p[3 * n + 1] = y;
            p[3 * n + 2] = x * x + y * y;
            n++;
        }
    check_set("paraboloid", p, n, 1);
    /* a plane of grid points plus one apex at a denormal height */
    n = 0;
    for (int x = 0; x < 15; x++)
        for (int y = 0; y < 15; y++) {
            p[3 * n] = x;
            p[3 * n + 1] = y;
            p[3 * n + 2] = 0;
            n++;
        }
    p[3 * n] = 7;
    p[3 * n + 1] = 7;
    p[3 * n + 2] = 0x1p-1074;
    n++;
    check_set("plane + denormal apex", p, n, 1);
    free(p);
}

static void test_scales_2_pow_minus_1000_and_2_pow_1000_and_mixed(void)
{
    const double scales[] = {0x1p-1000, 0x1p1000, 0x1p-1070};
    for (int s = 0; s < 3; s++) {
        size_t n;
        double *p = grid(5, &n);
        for (size_t i = 0; i < 3 * n; i++) p[i] *= scales[s];
        check_set("scaled grid", p, n, 1);
        free(p);
        p = uniform(500, 9 + (uint64_t)s);
        for (size_t i = 0; i < 3 * 500; i++) p[i] *= scales[s];
        check_set("scaled uniform", p, 500, 1);
        free(p);
    }
    /* mixed: a unit cluster plus points near 2^-1000 and 2^600 */
    double *p = uniform(300, 5);
    for (size_t i = 0; i < 100; i++)
        for (int d = 0; d < 3; d++) p[3 * i + d] *= 0x1p-1000;
    for (size_t i = 100; i < 110; i++)
        for (int d = 0; d < 3; d++) p[3 * i + d] *= 0x1p600;
    check_set("mixed scales", p, 300, 1);
    free(p);
}

static void test_duplicates_with_signed_zeros_are_mapped_not_dropped(void)
{
    double p[] = {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,  -0.0, 0, -0.0,  1, 0, 0,
                  1, 1, 1,  0, -0.0, 1};
    size_t n = sizeof p / sizeof *p / 3;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(p, n, NULL, &m);
    TEST_REQUIRE(s == GTET_OK, "status %d", s);
    TEST_CHECK(gtet_mesh_num_points(m) == 8, "points %zu", gtet_mesh_num_points(m));
    TEST_CHECK(gtet_mesh_num_vertices(m) == 5, "vertices %zu", gtet_mesh_num_vertices(m));
    TEST_CHECK(gtet_mesh_num_duplicates(m) == 3, "duplicates %zu", gtet_mesh_num_duplicates(m));
    const uint32_t *map = gtet_mesh_input_map(m);
    TEST_CHECK(map[4] == map[0] && map[5] == map[1] && map[7] == map[3], "duplicates mapped wrong");
    TEST_CHECK(map[0] != map[1] && map[6] == 4, "distinct points mapped wrong");
    gtet_check_report rep;
    TEST_CHECK(gtet_check(m, p, n, GTET_CHECK_FULL, &rep) == GTET_OK, "%s", rep.message);
    gtet_mesh_free(&m);
    TEST_CHECK(m == NULL, "gtet_mesh_free leaves the pointer set");
}

static void expect_degenerate(const char *name, const double *p, size_t n, int dim)
{
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.error = &err;
    gtet_mesh *m = (gtet_mesh *)&o;  /* must be reset to NULL */
    gtet_status s = gtet_triangulate(p, n, &o, &m);
    TEST_CHECK(s == GTET_ERR_DEGENERATE_INPUT, "%s: status %d, expected degenerate", name, s);
    TEST_CHECK(m == NULL, "%s: mesh not NULL on failure", name);
    TEST_CHECK(err.dimension == dim, "%s: dimension %d, expected %d (%s)", name, err.dimension,
               dim, err.message);
}

static void test_degenerate_input_reports_its_dimension(void)
{
    double p[3 * 400] = {0};
    expect_degenerate("empty", p, 0, -1);
    for (int i = 0; i < 50; i++) p[3 * i] = p[3 * i + 1] = p[3 * i + 2] = 1.5;
    expect_degenerate("all equal", p, 50, 0);
    for (int i = 0; i < 50; i++) {
        p[3 * i] = 0.1 * i;  /* rounded, but exactly on the line x = y = z */
        p[3 * i + 1] = 0.1 * i;
        p[3 * i + 2] = 0.1 * i;
    }
    expect_degenerate("collinear", p, 50, 1);
    tu_rng r = {3};
    for (int i = 0; i < 400; i++) {
        p[3 * i] = tu_uniform(&r);
        p[3 * i + 1] = tu_uniform(&r);
        p[3 * i + 2] = 0.25;
    }
    expect_degenerate("coplanar", p, 400, 2);
    expect_degenerate("three points", p, 3, 2);
    expect_degenerate("two points", p, 2, 1);
    expect_degenerate("one point", p, 1, 0);
}

static void test_nan_and_inf_name_the_input_index(void)
{
    double *p = uniform(100, 4);
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.error = &err;
    gtet_mesh *m = NULL;
    p[3 * 57 + 1] = NAN;
    TEST_CHECK(gtet_triangulate(p, 100, &o, &m) == GTET_ERR_NONFINITE && err.index == 57,
               "NaN at 57: index %zu (%s)", err.index, err.message);
    p[3 * 57 + 1] = 0.5;
    p[3 * 12 + 2] = -INFINITY;
    TEST_CHECK(gtet_triangulate(p, 100, &o, &m) == GTET_ERR_NONFINITE && err.index == 12,
               "Inf at 12: index %zu (%s)", err.index, err.message);
    TEST_CHECK(m == NULL, "mesh set on failure");
    TEST_CHECK(gtet_triangulate(NULL, 5, &o, &m) == GTET_ERR_ARGUMENT, "NULL points accepted");
    TEST_CHECK(gtet_triangulate(p, 5, &o, NULL) == GTET_ERR_ARGUMENT, "NULL out accepted");
    free(p);
    /* many points, several threads (the scan is split): still the first bad point, and the
     * coordinate it names */
    const size_t nb = 300000;
    p = uniform(nb, 5);
    p[3 * 290001 + 0] = NAN;      /* in the second thread's half */
    p[3 * 200000 + 2] = INFINITY;  /* the first one, also in the second half with 2 threads */
    p[3 * 250000 + 1] = -NAN;
    for (int th = 1; th <= 4; th++) {
        o.threads = th;
        TEST_CHECK(gtet_triangulate(p, nb, &o, &m) == GTET_ERR_NONFINITE && err.index == 200000 &&
                       strstr(err.message, "point 200000 has an infinite z") != NULL,
                   "%d threads: index %zu (%s), expected 200000, 'has an infinite z' (E155)", th,
                   err.index, err.message);
    }
    p[3 * 200000 + 2] = 0.5;
    p[3 * 7 + 0] = -INFINITY;  /* in the first thread's part */
    o.threads = 2;
    TEST_CHECK(gtet_triangulate(p, nb, &o, &m) == GTET_ERR_NONFINITE && err.index == 7,
               "2 threads: index %zu (%s), expected 7", err.index, err.message);
    free(p);
}

static void test_check_option_runs_the_checker(void)
{
    double *p = uniform(2000, 8);
    gtet_options o;
    gtet_options_init(&o);
    o.check = 1;
    gtet_mesh *m = NULL;
    TEST_CHECK(gtet_triangulate(p, 2000, &o, &m) == GTET_OK, "check option fails");
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    TEST_CHECK(st.pred.insphere_calls > 0 && st.pred.orient_calls > 0, "no predicate counts");
    TEST_CHECK(st.num_rounds >= 1 && st.rounds != NULL, "no round statistics");
    gtet_mesh_free(&m);
    free(p);
}

/* Exercises proofs/perturbation.md P6: two big coplanar, cocircular hull faces (integer grids on
 * z = 0 and z = 3) and a few interior points, inserted in several orders, give one mesh. */
static void test_points_inserted_on_a_coplanar_hull_face_give_the_same_mesh_in_any_order(void)
{
    size_t n = 0;
    double *p = malloc(3 * 200 * sizeof *p);
    for (int z = 0; z <= 3; z += 3)
        for (int x = 0; x < 8; x++)
            for (int y = 0; y < 8; y++) {
                p[3 * n] = x;
                p[3 * n + 1] = y;
                p[3 * n + 2] = z;
                n++;
            }
    const double inner[4][3] = {{3.5, 3.5, 1.5}, {1, 6, 2}, {6, 1, 1}, {2.25, 2.75, 0.5}};
    for (int i = 0; i < 4; i++, n++)
        for (int d = 0; d < 3; d++) p[3 * n + d] = inner[i][d];
    for (uint64_t seed = 1; seed <= 3; seed++) {
        shuffle(p, n, seed);
        check_set("two coplanar hull faces", p, n, (int)seed);  /* 1, 2, 3 threads */
    }
    free(p);
}

/* proofs/termination.md T1.4: the visibility walk never needs its scan fallback. */
static void test_walks_never_fall_back_to_the_scan(void)
{
    size_t n;
    double *sets[3];
    size_t sizes[3];
    sets[0] = uniform(BIG(20000), 31);
    sizes[0] = BIG(20000);
    sets[1] = grid(BIG(20 * 8) / 8 > 10 ? 20 : 10, &n);
    sizes[1] = n;
    sets[2] = cospherical(325, &n);
    sizes[2] = n;
    for (int k = 0; k < 3; k++) {
        for (int th = 1; th <= 2; th++) {
            gtet_options o;
            gtet_options_init(&o);
            o.threads = th;
            gtet_mesh *m = NULL;
            TEST_REQUIRE(gtet_triangulate(sets[k], sizes[k], &o, &m) == GTET_OK, "set %d fails", k);
            gtet_stats st;
            gtet_mesh_stats(m, &st);
            TEST_CHECK(st.walk_fallbacks == 0, "set %d, %d threads: %llu walk fallbacks", k, th,
                       (unsigned long long)st.walk_fallbacks);
            TEST_CHECK(st.walk_steps > 0, "set %d: no walk steps counted", k);
            gtet_mesh_free(&m);
        }
        free(sets[k]);
    }
}

/* proofs/termination.md T3, T4: every distinct point inserted once; one thread defers nothing. */
static void test_rounds_insert_every_point_once_and_one_thread_defers_nothing(void)
{
    const size_t np = BIG(60000);
    double *p = uniform(np, 41);
    for (int th = 1; th <= 2; th++) {
        gtet_options o;
        gtet_options_init(&o);
        o.threads = th;
        gtet_mesh *m = NULL;
        TEST_REQUIRE(gtet_triangulate(p, np, &o, &m) == GTET_OK, "triangulate fails");
        gtet_stats st;
        gtet_mesh_stats(m, &st);
        uint64_t sum = 0;
        for (int r = 0; r < st.num_rounds; r++) {
            const gtet_round_stats *rs = &st.rounds[r];
            sum += rs->inserted;
            TEST_CHECK(rs->inserted == rs->points, "round %d: %llu of %llu inserted", r,
                       (unsigned long long)rs->inserted, (unsigned long long)rs->points);
            if (th == 1)
                TEST_CHECK(rs->deferred == 0 && rs->passes == 1 && rs->tried == rs->points,
                           "one thread, round %d: %llu deferred in %d passes", r,
                           (unsigned long long)rs->deferred, rs->passes);
            /* alpha of the first pass: 1 exactly when it inserted everything; otherwise at
             * least what the round's deferrals (all passes) leave */
            const double a = rs->alpha_first, lo = 1.0 - (double)rs->deferred / (double)rs->points;
            TEST_CHECK(rs->passes == 1 ? a == 1.0 : (a < 1.0 && a >= lo - 1e-12),
                       "%d threads, round %d: alpha of the first pass %g (%d passes, %llu deferred "
                       "of %llu)", th, r, a, rs->passes, (unsigned long long)rs->deferred,
                       (unsigned long long)rs->points);
        }
        TEST_CHECK(sum + 4 == gtet_mesh_num_vertices(m), "%d threads: %llu inserted + 4 != %zu",
                   th, (unsigned long long)sum, gtet_mesh_num_vertices(m));
        gtet_mesh_free(&m);
    }
    free(p);
}

/* proofs/termination.md T5: with 2 threads a round ends within log2(points) + 2 passes, and
 * the big rounds really run on 2 threads. */
static void test_parallel_rounds_end_within_the_pass_bound(void)
{
    size_t n;
    double *sets[2];
    size_t sizes[2];
    sets[0] = uniform(BIG(100000), 51);
    sizes[0] = BIG(100000);
    sets[1] = grid(BIG(40 * 8) / 8 > 20 ? 40 : 20, &n);
    sizes[1] = n;
    for (int k = 0; k < 2; k++) {
        gtet_options o;
        gtet_options_init(&o);
        o.threads = 2;
        gtet_mesh *m = NULL;
        TEST_REQUIRE(gtet_triangulate(sets[k], sizes[k], &o, &m) == GTET_OK, "set %d fails", k);
        gtet_stats st;
        gtet_mesh_stats(m, &st);
        int parallel_rounds = 0;
        for (int r = 0; r < st.num_rounds; r++) {
            const gtet_round_stats *rs = &st.rounds[r];
            double bound = 2.0;
            for (uint64_t q = rs->points; q > 1; q /= 2) bound += 1.0;
            TEST_CHECK(rs->passes <= bound, "set %d round %d: %d passes for %llu points", k, r,
                       rs->passes, (unsigned long long)rs->points);
            TEST_CHECK(rs->inserted == rs->points, "set %d round %d: not all inserted", k, r);
            if (rs->threads == 2) parallel_rounds++;
        }
        TEST_CHECK(parallel_rounds >= 1, "set %d: no round used 2 threads", k);
        gtet_mesh_free(&m);
        free(sets[k]);
    }
}

int main(void)
{
    TU_RUN(test_random_sets_of_many_sizes_pass_the_exact_checker);
    TU_RUN(test_integer_grids_every_insphere_degenerate_are_perturbed_consistently);
    TU_RUN(test_cospherical_integer_points_are_triangulated_uniquely);
    TU_RUN(test_cube_corners_and_centre);
    TU_RUN(test_lattices_paraboloid_and_plane_with_denormal_apex);
    TU_RUN(test_scales_2_pow_minus_1000_and_2_pow_1000_and_mixed);
    TU_RUN(test_duplicates_with_signed_zeros_are_mapped_not_dropped);
    TU_RUN(test_degenerate_input_reports_its_dimension);
    TU_RUN(test_nan_and_inf_name_the_input_index);
    TU_RUN(test_check_option_runs_the_checker);
    TU_RUN(test_points_inserted_on_a_coplanar_hull_face_give_the_same_mesh_in_any_order);
    TU_RUN(test_walks_never_fall_back_to_the_scan);
    TU_RUN(test_rounds_insert_every_point_once_and_one_thread_defers_nothing);
    TU_RUN(test_parallel_rounds_end_within_the_pass_bound);
    return tu_finish();
}
