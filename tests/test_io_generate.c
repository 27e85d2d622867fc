/* test_io_generate.c -- every generator kind keeps its promise exactly (integer lattices,
 * co-spherical points on one sphere, the lifted paraboloid, the denormal apex), is
 * reproducible from its seed, and refuses unknown kinds and empty sizes.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/io.h"
#include "testutil.h"

static double *gen(const char *kind, size_t n, uint64_t seed, size_t *m)
{
    double *p;
    io_error e;
    if (io_generate(kind, n, seed, &p, m, &e) != IO_OK) {
        tu_fail(__FILE__, __LINE__, "generate %s %zu: %s", kind, n, e.message);
        return NULL;
    }
    return p;
}

static void test_every_kind_is_finite_and_reproducible_from_its_seed(void)
{
    for (const char *const *k = io_generator_kinds(); *k; k++) {
        if (!strcmp(*k, "surface")) continue; /* needs a mesh: test_io_surface.c */
        size_t m1, m2, m3;
        double *a = gen(*k, 500, 3, &m1), *b = gen(*k, 500, 3, &m2), *c = gen(*k, 500, 4, &m3);
        TEST_REQUIRE(a && b && c, "%s failed", *k);
        TEST_CHECK(m1 >= 4 && m1 == m2 && memcmp(a, b, 3 * m1 * sizeof(double)) == 0,
                   "%s is not reproducible", *k);
        TEST_CHECK(m1 >= 250 && m1 <= 1000, "%s gave %zu points for 500", *k, m1);
        for (size_t i = 0; i < 3 * m1; i++) TEST_CHECK(isfinite(a[i]), "%s: non-finite", *k);
        TEST_CHECK(io_generator_help(*k) != NULL, "%s has no help", *k);
        int random = !strcmp(*k, "uniform") || !strcmp(*k, "ball") || !strcmp(*k, "sphere") ||
                     !strcmp(*k, "jittered") || !strcmp(*k, "clustered") ||
                     !strcmp(*k, "far-point") || !strcmp(*k, "cauchy");
        if (random)
            TEST_CHECK(m1 != m3 || memcmp(a, c, 3 * m1 * sizeof(double)) != 0,
                       "%s ignores its seed", *k);
        free(a);
        free(b);
        free(c);
    }
}

static void test_random_kinds_give_exactly_n_points_in_their_domains(void)
{
    size_t m;
    double *p = gen("uniform", 1000, 1, &m);
    TEST_REQUIRE(p && m == 1000, "uniform count");
    for (size_t i = 0; i < 3 * m; i++) TEST_CHECK(p[i] >= 0 && p[i] < 1, "uniform out of [0,1)");
    free(p);
    p = gen("ball", 1000, 1, &m);
    TEST_REQUIRE(p && m == 1000, "ball count");
    for (size_t i = 0; i < m; i++) {
        double q = p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2];
        TEST_CHECK(q <= 1.0, "ball point %zu outside", i);
    }
    free(p);
    p = gen("sphere", 1000, 1, &m);
    TEST_REQUIRE(p && m == 1000, "sphere count");
    for (size_t i = 0; i < m; i++) {
        double q = sqrt(p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2]);
        TEST_CHECK(fabs(q - 1.0) < 1e-15, "sphere point %zu at radius %.17g", i, q);
    }
    free(p);
    p = gen("clustered", 3000, 1, &m);
    TEST_CHECK(p && m == 3000, "clustered count");
    free(p);
    p = gen("far-point", 3000, 1, &m);
    TEST_REQUIRE(p && m == 3000, "far-point count");
    for (size_t i = 0; i + 3 < 3 * m; i++) TEST_CHECK(p[i] >= 0 && p[i] < 1, "far-point bulk");
    TEST_CHECK(p[3 * m - 3] == 1e6 && p[3 * m - 2] == 1e6 && p[3 * m - 1] == 1e6, "far point");
    free(p);
    p = gen("cauchy", 20000, 1, &m);
    TEST_REQUIRE(p && m == 20000, "cauchy count");
    size_t tail = 0, inner = 0;  /* P(|X| > 100) = 0.64%, P(|X| < 1) = 50% */
    for (size_t i = 0; i < 3 * m; i++) {
        tail += fabs(p[i]) > 100;
        inner += fabs(p[i]) < 1;
    }
    TEST_CHECK(tail > 200 && tail < 600 && inner > 28000 && inner < 32000,
               "cauchy: %zu of 60000 beyond 100, %zu within 1", tail, inner);
    free(p);
}

static void test_grid_rounds_to_a_cube_of_integers(void)
{
    size_t m;
    double *p = gen("grid", 30, 1, &m);
    TEST_REQUIRE(p && m == 27, "grid 30 -> %zu points, expected 3^3", m);
    for (size_t i = 0; i < 3 * m; i++) TEST_CHECK(p[i] == floor(p[i]) && p[i] >= 0 && p[i] <= 2, "grid value");
    free(p);
    p = gen("grid", 1000, 1, &m);
    TEST_CHECK(p && m == 1000, "grid 1000 -> %zu", m);
    free(p);
    p = gen("jittered", 1000, 1, &m);
    TEST_REQUIRE(p && m == 1000, "jittered count");
    for (size_t i = 0; i < 3 * m; i++)
        TEST_CHECK(fabs(p[i] - nearbyint(p[i])) <= 0x1p-20, "jitter too large: %a", p[i]);
    free(p);
}

static void test_cospherical_points_lie_exactly_on_one_integer_sphere(void)
{
    size_t m;
    double *p = gen("cospherical", 600, 1, &m);
    TEST_REQUIRE(p, "cospherical failed");
    TEST_CHECK(m >= 300 && m <= 1200, "cospherical gave %zu points for 600", m);
    double r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    for (size_t i = 0; i < m; i++) {
        double q = p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2];
        TEST_CHECK(q == r2, "point %zu: x^2+y^2+z^2 = %.17g != %.17g", i, q, r2);
        for (size_t j = 0; j < i; j++)
            TEST_CHECK(memcmp(p + 3 * i, p + 3 * j, 24) != 0, "points %zu and %zu coincide", i, j);
    }
    free(p);
}

static void test_paraboloid_and_lattices_are_exact(void)
{
    size_t m;
    double *p = gen("paraboloid", 400, 1, &m);
    TEST_REQUIRE(p && m >= 361 && m <= 441, "paraboloid gave %zu", m);
    for (size_t i = 0; i < m; i++)
        TEST_CHECK(p[3 * i + 2] == p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1], "not lifted");
    free(p);
    p = gen("fcc", 1000, 1, &m);
    TEST_REQUIRE(p, "fcc");
    for (size_t i = 0; i < m; i++)
        TEST_CHECK(fmod(p[3 * i] + p[3 * i + 1] + p[3 * i + 2], 2.0) == 0, "fcc point %zu odd", i);
    free(p);
    p = gen("bcc", 1000, 1, &m);
    TEST_REQUIRE(p, "bcc");
    for (size_t i = 0; i < m; i++) {
        int a = (int)fmod(p[3 * i], 2.0), b = (int)fmod(p[3 * i + 1], 2.0), c = (int)fmod(p[3 * i + 2], 2.0);
        TEST_CHECK(a == b && b == c, "bcc point %zu mixed parity", i);
    }
    free(p);
}

static void test_plane_apex_puts_all_but_the_apex_on_z_zero(void)
{
    size_t m;
    double *p = gen("plane-apex-denormal", 100, 1, &m);
    TEST_REQUIRE(p && m == 100, "plane-apex-denormal count");
    for (size_t i = 0; i + 1 < m; i++) TEST_CHECK(p[3 * i + 2] == 0, "point %zu off the plane", i);
    TEST_CHECK(p[3 * m - 1] == 0x1p-1074, "apex height %a", p[3 * m - 1]);
    free(p);
    p = gen("plane-apex", 100, 1, &m);
    TEST_REQUIRE(p && m == 100, "plane-apex count");
    TEST_CHECK(p[3 * m - 1] == 1.0, "apex height %a", p[3 * m - 1]);
    free(p);
}

static void test_unknown_kinds_and_empty_sizes_are_argument_errors(void)
{
    double *p;
    size_t m;
    io_error e;
    TEST_CHECK(io_generate("cube", 10, 1, &p, &m, &e) == IO_ERR_ARGUMENT && strstr(e.message, "cube"),
               "unknown kind accepted");
    TEST_CHECK(io_generate("uniform", 0, 1, &p, &m, &e) == IO_ERR_ARGUMENT, "n = 0 accepted");
    TEST_CHECK(io_generate("surface", 10, 1, &p, &m, &e) == IO_ERR_ARGUMENT && p == NULL &&
                   strstr(e.message, "--mesh"), "surface without a mesh: %s", e.message);
    TEST_CHECK(p == NULL && m == 0, "outputs not cleared");
}

int main(void)
{
    TU_RUN(test_every_kind_is_finite_and_reproducible_from_its_seed);
    TU_RUN(test_random_kinds_give_exactly_n_points_in_their_domains);
    TU_RUN(test_grid_rounds_to_a_cube_of_integers);
    TU_RUN(test_cospherical_points_lie_exactly_on_one_integer_sphere);
    TU_RUN(test_paraboloid_and_lattices_are_exact);
    TU_RUN(test_plane_apex_puts_all_but_the_apex_on_z_zero);
    TU_RUN(test_unknown_kinds_and_empty_sizes_are_argument_errors);
    return tu_finish();
}
