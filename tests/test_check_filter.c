/* test_check_filter.c -- the checker's interval filter (src/check/check_filter.c) never changes a
 * sign: with the filter, every orient3d / perturbed insphere / hull-rule sign equals the GMP
 * oracle's, on families chosen to defeat a wrong bound: near-degenerate (1-ulp) tuples,
 * integer grids (exact zeros), overflowing (2^1023) and underflowing (subnormal) magnitudes,
 * mixed scales.  And the whole checker gives the same verdicts with and without the filter.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "check/check_internal.h"
#include "oracle/oracle.h"
#include "test_check_meshes.h"
#include "testutil.h"

static double coord(tu_rng *r, int family, double base)
{
    double u = tu_uniform(r) - 0.5;
    switch (family) {
    case 0: return u;
    case 1: return (double)((int)tu_below(r, 3));                      /* grid: exact zeros */
    case 2: return ldexp(u, 1023);                                     /* overflow */
    case 3: return ldexp(u, -1070);                                    /* subnormal */
    case 4: return tu_below(r, 2) ? ldexp(u, 600) : ldexp(u, -600);    /* mixed */
    case 5: return nextafter(base, tu_below(r, 2) ? 2.0 : -2.0);       /* 1 ulp from base */
    default: return u * DBL_MAX;                                       /* the whole range */
    }
}

static void test_filtered_signs_equal_the_oracle_on_adversarial_families(void)
{
    chk_ctx c;
    memset(&c, 0, sizeof c);
    tu_rng r = {2024};
    long decided = 0, total = 0;
    for (int it = 0; it < 7000; it++) {
        int fam = it % 7;
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = coord(&r, fam, 0.5 * (double)(i + j));
        if (fam == 5) {
            /* five points 1 ulp off a plane through the first three */
            for (int j = 0; j < 3; j++) p[3][j] = nextafter(p[0][j] + p[1][j] - p[2][j], 0.0);
        }
        c.flags = 0;
        int o = chk_orient3d(&c, p[0], p[1], p[2], p[3]);
        TEST_CHECK(o == orc_orient3d(p[0], p[1], p[2], p[3]), "orient3d differs, family %d", fam);
        int s = chk_insphere_sos(&c, p[0], p[1], p[2], p[3], p[4]);
        TEST_CHECK(s == orc_insphere_sos(p[0], p[1], p[2], p[3], p[4]), "insphere differs, family %d", fam);
        int g = chk_ghost_conflict(&c, p[0], p[1], p[2], p[3]);
        TEST_CHECK(g == orc_ghost_conflict(p[0], p[1], p[2], p[3]), "ghost differs, family %d", fam);
        /* how often the filter alone decided (the oracle's zero is never decided by it) */
        c.flags = GTET_CHECK_NO_FILTER;
        TEST_CHECK(chk_orient3d(&c, p[0], p[1], p[2], p[3]) == o, "NO_FILTER differs");
        total++;
        decided += orc_orient3d(p[0], p[1], p[2], p[3]) != 0;
    }
    TEST_CHECK(decided > total / 2 && decided < total, "families too easy or too hard: %ld of %ld",
               decided, total);
}

static void test_checker_verdicts_do_not_depend_on_the_filter(void)
{
    for (uint64_t seed = 40; seed < 44; seed++) {
        double *p = tm_random_points(seed, 14);
        if (seed == 42)  /* 14 points of a 3x3x2 grid: many exact zeros */
            for (int i = 0; i < 14; i++) {
                p[3 * i] = i % 3;
                p[3 * i + 1] = (i / 3) % 3;
                p[3 * i + 2] = i / 9;
            }
        tmesh m = tm_brute_delaunay(p, 14);
        for (int mutate = 0; mutate < 2; mutate++) {
            if (mutate) {
                uint32_t x = m.t[1];
                m.t[1] = m.t[2];
                m.t[2] = x;
            }
            gtet_check_report a, b;
            gtet_status sa = tm_check(&m, p, 14, GTET_CHECK_FULL, &a);
            gtet_status sb = tm_check(&m, p, 14, GTET_CHECK_FULL | GTET_CHECK_NO_FILTER, &b);
            TEST_CHECK(sa == sb && strcmp(a.message, b.message) == 0,
                       "seed %llu mutate %d: filtered '%s' vs oracle '%s'",
                       (unsigned long long)seed, mutate, a.message, b.message);
            TEST_CHECK((sa == GTET_OK) == !mutate, "seed %llu mutate %d: %s",
                       (unsigned long long)seed, mutate, a.message);
        }
        tm_free(&m);
        free(p);
    }
}

int main(void)
{
    TU_RUN(test_filtered_signs_equal_the_oracle_on_adversarial_families);
    TU_RUN(test_checker_verdicts_do_not_depend_on_the_filter);
    return tu_finish();
}
