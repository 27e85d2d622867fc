/* test_pred_scaled_filter.c -- the filters' scaled retry (src/pred/filter_scaled.c,
 * proofs/filters.md section 11): tuples whose translated coordinates are all tiny or all huge
 * (a cluster near 10^-300 or 10^300) are outside the window the filter constants are proved
 * for; the exact chains (pred_orient3d_exact, pred_insphere_exact) then first run the filter
 * on the translations scaled by a power of two, which decides there.
 *
 * Specification: on every tuple the filter is undecided (0) or gives the exact sign (src/oracle,
 * independent mpz arithmetic); on random tuples of one cluster at scales 2^-1070 .. 2^1000 it
 * decides nearly all (without the retry it decides none: the liveness half, which fails when
 * the retry answers 0); on ulp neighbours of exactly co-spherical and coplanar tuples,
 * points rounded onto a sphere, and tuples with one tiny translated coordinate at a huge scale
 * (the scaling's exactness check) it is never wrong.
 */
#include "oracle/oracle.h"
#include "pred/filter.h"
#include "pred_gen.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

static const int scales[] = {-1070, -1000, -800, -600, -400, -300, -250, 250, 300, 400, 600,
                             800, 900, 1000};
#define NSCALES ((int)(sizeof scales / sizeof scales[0]))

typedef struct tally { long tuples, decided, wrong; } tally;

static void judge(double (*p)[3], int is, tally *t)
{
    int f, ref;
    /* the inline filter, then the retry the exact chains start with */
    if (is) {
        f = pred_insphere_filter(p[0], p[1], p[2], p[3], p[4], PRED_NO_STATIC, NULL);
        if (f == 0) f = pred_insphere_filter_scaled(p[0], p[1], p[2], p[3], p[4]);
        ref = orc_insphere(p[0], p[1], p[2], p[3], p[4]);
    } else {
        f = pred_orient3d_filter(p[0], p[1], p[2], p[3], PRED_NO_STATIC);
        if (f == 0) f = pred_orient3d_filter_scaled(p[0], p[1], p[2], p[3]);
        ref = orc_orient3d(p[0], p[1], p[2], p[3]);
    }
    t->tuples++;
    t->decided += f != 0;
    if (f != 0 && f != ref) {
        t->wrong++;
        if (t->wrong <= 3)
            TEST_CHECK(0, "%s filter %d, exact %d at (%a %a %a) ... (%a %a %a)",
                       is ? "insphere" : "orient3d", f, ref, p[0][0], p[0][1], p[0][2],
                       p[is ? 4 : 3][0], p[is ? 4 : 3][1], p[is ? 4 : 3][2]);
    }
}

/* a cluster: an offset near 2^k plus points of extent about 2^k (each coordinate rounded) */
static void random_tuple(tu_rng *r, double (*p)[3], int n, int k, int offset)
{
    const double o[3] = {offset ? ldexp(1.0 + tu_uniform(r), k + 2) : 0.0, 0.0, 0.0};
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) p[i][j] = o[j] + ldexp(tu_uniform(r), k);
}

static void test_random_clusters_are_decided_and_exact(void)
{
    tu_rng r = {11};
    for (int is = 0; is < 2; is++)
        for (int q = 0; q < NSCALES; q++) {
            tally t = {0, 0, 0};
            double p[5][3];
            for (int it = 0; it < 400; it++) {
                random_tuple(&r, p, is ? 5 : 4, scales[q], it & 1);
                judge(p, is, &t);
            }
            TEST_CHECK(t.wrong == 0, "scale 2^%d: %ld wrong", scales[q], t.wrong);
            /* subnormal clusters are coarse lattices: exact zeros happen; otherwise nearly all */
            const long need = scales[q] <= -1000 ? t.tuples / 2 : t.tuples * 9 / 10;
            TEST_CHECK(t.decided >= need, "%s at scale 2^%d: %ld of %ld decided",
                       is ? "insphere" : "orient3d", scales[q], t.decided, t.tuples);
        }
}

/* ulp neighbours of exactly degenerate tuples (integer lattice sphere / plane, scaled by a power
 * of two, so still exactly degenerate) and points rounded onto a sphere, at every scale */
static void test_near_degenerate_tuples_are_never_wrong(void)
{
    tu_rng r = {12};
    int64_t lat[400][3];
    const int nl = pg_sphere_lattice(7225, lat, 400); /* 85^2: many lattice points */
    TEST_REQUIRE(nl >= 5, "lattice points");
    tally ti = {0, 0, 0}, to = {0, 0, 0};
    for (int q = 0; q < NSCALES; q++)
        for (int it = 0; it < 300; it++) {
            double p[5][3];
            const int k = scales[q] - 7;
            for (int i = 0; i < 5; i++) {
                const int64_t *l = lat[tu_below(&r, (uint64_t)nl)];
                for (int j = 0; j < 3; j++) p[i][j] = ldexp((double)l[j], k);
            }
            if (it % 3) pg_perturb(&r, p, 5);
            judge(p, 1, &ti);
            /* coplanar: the first three and a combination of them */
            for (int j = 0; j < 3; j++) p[3][j] = p[0][j] + (p[1][j] - p[0][j]);
            if (it % 3) pg_perturb(&r, p, 4);
            judge(p, 0, &to);
            /* rounded onto a sphere of radius 2^scale */
            for (int i = 0; i < 5; i++) {
                double v[3], n2 = 0.0;
                for (int j = 0; j < 3; j++) {
                    v[j] = tu_uniform(&r) - 0.5;
                    n2 += v[j] * v[j];
                }
                for (int j = 0; j < 3; j++) p[i][j] = ldexp(v[j] / sqrt(n2), scales[q]);
            }
            judge(p, 1, &ti);
        }
    TEST_CHECK(ti.wrong == 0 && to.wrong == 0, "insphere %ld, orient3d %ld wrong of %ld / %ld",
               ti.wrong, to.wrong, ti.tuples, to.tuples);
}

/* at a huge scale, translations whose small entries do not survive the scaling down (they would
 * round below 2^-1022): the filter must stay exact (undecided or right) */
static void test_tiny_entries_at_huge_scales(void)
{
    tu_rng r = {13};
    tally t = {0, 0, 0};
    for (int it = 0; it < 3000; it++) {
        const int is = it & 1;
        double p[5][3];
        const int k = 900 + (int)tu_below(&r, 100);
        random_tuple(&r, p, is ? 5 : 4, k, 0);
        /* one coordinate of one point moved by a tiny (maybe subnormal) amount off another's */
        const int i = (int)tu_below(&r, is ? 5 : 4), j = (int)tu_below(&r, 3);
        const int i2 = (i + 1) % (is ? 5 : 4);
        p[i][j] = p[i2][j];
        if (tu_below(&r, 2)) p[i][j] = pg_ulps(p[i][j], (int)tu_below(&r, 5) - 2);
        p[i][(j + 1) % 3] = pg_double_exp(&r, -1074, -900);
        p[i2][(j + 1) % 3] = 0.0;
        judge(p, is, &t);
    }
    TEST_CHECK(t.wrong == 0, "%ld wrong of %ld", t.wrong, t.tuples);
}

int main(void)
{
    TU_RUN(test_random_clusters_are_decided_and_exact);
    TU_RUN(test_near_degenerate_tuples_are_never_wrong);
    TU_RUN(test_tiny_entries_at_huge_scales);
    return tu_finish();
}
