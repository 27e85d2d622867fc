/* test_pred_signs_match_oracle.c -- every stage of orient3d and insphere gives the exact sign.
 *
 * Specification: for every tuple of finite doubles, the filter is either undecided (0) or
 * equal to the exact sign; each exact stage (small integers, expansions, GMP) equals the exact
 * sign whenever it accepts the tuple; the whole chain and the public gtet_ wrappers equal it;
 * the filter given a static bound (the tuple's own box extents, filters.md section 8) is
 * undecided or exact, and a zero static bound must err somewhere (the pre-check is live).
 * The exact sign is src/oracle (an independent mpz implementation).  Tuples: random doubles,
 * 1-2 ulp neighbours of exactly coplanar / co-spherical configurations, integer grids at the
 * int64 / __int128 / expansion boundaries, lattice points of integer spheres, points rounded
 * onto a sphere, subnormals, 2^-1074, 2^1000 and mixed scales.  The test also requires each
 * stage to have been exercised (and the filter to decide most random tuples) so that a stage
 * silently never running fails it.
 */
#include "oracle/oracle.h"
#include "pred/filter.h"
#include "pred/pred_internal.h"
#include "pred_gen.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

typedef struct stage_stats {
    long tuples, filter_decided, zero_bound_wrong, int_used, wide_used, wide122_used, exp_used,
        zero, bad;
} stage_stats;

/* The computed extents of the tuple's box: the static bounds a caller holding exactly these
 * points may pass (filter.h, proofs/filters.md section 8). */
static void box_extents(double (*p)[3], int n, double ext[3])
{
    for (int j = 0; j < 3; j++) {
        double lo = p[0][j], hi = p[0][j];
        for (int i = 1; i < n; i++) {
            if (p[i][j] < lo) lo = p[i][j];
            if (p[i][j] > hi) hi = p[i][j];
        }
        ext[j] = hi - lo;
    }
}

static stage_stats so, si; /* orient3d, insphere */

static void check_orient(double (*p)[3])
{
    const double *a = p[0], *b = p[1], *c = p[2], *d = p[3];
    int ref = orc_orient3d(a, b, c, d), s;
    gtet_pred_counters cnt;
    memset(&cnt, 0, sizeof cnt);
    so.tuples++;
    so.zero += ref == 0;
    int f = pred_orient3d_filter(a, b, c, d, PRED_NO_STATIC);
    if (f) so.filter_decided++;
    int ok = (f == 0 || f == ref);
    double ext[3];
    box_extents(p, 4, ext);
    const double seps = pred_orient3d_static_eps(ext[0], ext[1], ext[2]);
    int fs = pred_orient3d_filter(a, b, c, d, seps);
    ok &= fs == 0 || fs == ref;
    /* liveness of the static pre-check: a bound of 0 lets it answer the rounded sign */
    const int f0 = pred_orient3d_filter(a, b, c, d, 0.0);
    so.zero_bound_wrong += f0 != 0 && f0 != ref;
    if (pred_orient3d_int(a, b, c, d, &s)) so.int_used++, ok &= s == ref;
    if (pred_orient3d_wide(a, b, c, d, &s)) so.wide_used++, ok &= s == ref;
    if (pred_orient3d_exp(a, b, c, d, &s)) so.exp_used++, ok &= s == ref;
    if (so.tuples % 3 == 0) ok &= pred_orient3d_gmp(a, b, c, d) == ref; /* slow: a third */
    ok &= pred_orient3d(a, b, c, d, &cnt) == ref;
    ok &= gtet_orient3d(a, b, c, d) == ref;
    if (!ok && so.bad++ < 5)
        TEST_CHECK(0, "orient3d mismatch (ref %d) at (%a %a %a) (%a %a %a) (%a %a %a) (%a %a %a)",
                   ref, a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]);
}

static void check_insphere(double (*p)[3])
{
    const double *a = p[0], *b = p[1], *c = p[2], *d = p[3], *e = p[4];
    int ref = orc_insphere(a, b, c, d, e), s;
    gtet_pred_counters cnt;
    memset(&cnt, 0, sizeof cnt);
    si.tuples++;
    si.zero += ref == 0;
    int f = pred_insphere_filter(a, b, c, d, e, PRED_NO_STATIC, NULL);
    if (f) si.filter_decided++;
    int ok = (f == 0 || f == ref);
    double ext[3];
    box_extents(p, 5, ext);
    const double seps = pred_insphere_static_eps(ext[0], ext[1], ext[2]);
    int fs = pred_insphere_filter(a, b, c, d, e, seps, NULL);
    ok &= fs == 0 || fs == ref;
    const int f0 = pred_insphere_filter(a, b, c, d, e, 0.0, NULL);
    si.zero_bound_wrong += f0 != 0 && f0 != ref;
    if (pred_insphere_int(a, b, c, d, e, &s)) si.int_used++, ok &= s == ref;
    if (pred_insphere_wide(a, b, c, d, e, &s)) si.wide_used++, ok &= s == ref;
    if (pred_insphere_wide122(a, b, c, d, e, &s)) si.wide122_used++, ok &= s == ref;
    if (pred_insphere_exp(a, b, c, d, e, &s)) si.exp_used++, ok &= s == ref;
    if (si.tuples % 3 == 0) ok &= pred_insphere_gmp(a, b, c, d, e) == ref;
    ok &= pred_insphere(a, b, c, d, e, &cnt) == ref;
    ok &= gtet_insphere(a, b, c, d, e) == ref;
    if (!ok && si.bad++ < 5)
        TEST_CHECK(0, "insphere mismatch (ref %d) at (%a %a %a) (%a %a %a) (%a %a %a) (%a %a %a) "
                      "(%a %a %a)", ref, a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2],
                   d[0], d[1], d[2], e[0], e[1], e[2]);
}

static void check_both(double (*p)[3])
{
    check_orient(p);
    check_insphere(p);
}

static void reset(void)
{
    memset(&so, 0, sizeof so);
    memset(&si, 0, sizeof si);
}

static void report(const char *what)
{
    printf("  %-28s orient %6ld (filter %6ld int %6ld wide %6ld exp %6ld zero %6ld)\n"
           "  %-28s insphere %6ld (filter %6ld int %6ld wide %6ld exp %6ld zero %6ld)\n", what,
           so.tuples, so.filter_decided, so.int_used, so.wide_used, so.exp_used, so.zero, "",
           si.tuples, si.filter_decided, si.int_used, si.wide_used, si.exp_used, si.zero);
}

static void test_random_unit_doubles_match_oracle(void)
{
    tu_rng r = {1};
    reset();
    double p[5][3];
    for (int t = 0; t < 20000; t++) {
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = tu_uniform(&r);
        check_both(p);
    }
    report("random [0,1)");
    TEST_CHECK(so.filter_decided > so.tuples * 99 / 100, "filter decides too few orient3d");
    TEST_CHECK(si.filter_decided > si.tuples * 99 / 100, "filter decides too few insphere");
}

static void test_random_doubles_any_exponent_match_oracle(void)
{
    tu_rng r = {2};
    reset();
    double p[5][3];
    for (int t = 0; t < 6000; t++) {
        /* narrow spread around a random centre (scaled expansion path), or the full range */
        int wide = t % 3 == 0;
        int centre = -1000 + (int)tu_below(&r, 2001);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++)
                p[i][j] = wide ? pg_double_exp(&r, -1074, 1023)
                               : pg_double_exp(&r, centre - 12, centre + 12 > 1023 ? 1023 : centre + 12);
        if (t % 2) pg_perturb(&r, p, 5);
        check_both(p);
        /* the same tuple made degenerate: d (and e) copied from a on one coordinate axis */
        p[3][0] = p[0][0], p[3][1] = p[1][1], p[3][2] = p[2][2];
        check_both(p);
    }
    report("any exponent");
    /* insphere: random mantissas make p - e inexact, which insphere leaves to GMP */
    TEST_CHECK(so.exp_used > 2000, "orient3d expansion stage barely exercised");
}

/* Exactly coplanar points: d = a + s (b-a) + t (c-a) in integers, then scaled by 2^k (exact),
 * then 0-2 ulps moved. */
static void test_ulp_neighbours_of_coplanar_points_match_oracle(void)
{
    tu_rng r = {3};
    reset();
    for (int t = 0; t < 15000; t++) {
        int64_t q[5][3];
        int64_t m = (int64_t)1 << (4 + tu_below(&r, 26));
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) q[i][j] = pg_int(&r, m);
        for (int i = 3; i < 5; i++) {
            int64_t s = pg_int(&r, 4), u = pg_int(&r, 4);
            for (int j = 0; j < 3; j++)
                q[i][j] = q[0][j] + s * (q[1][j] - q[0][j]) + u * (q[2][j] - q[0][j]);
        }
        int k = (t % 4 == 0) ? 0 : -1070 + (int)tu_below(&r, 2050); /* finite: |q| < 2^36 */
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = ldexp((double)q[i][j], k);
        if (t % 3) pg_perturb(&r, p, 5);
        check_both(p);
    }
    report("coplanar + ulps");
    TEST_CHECK(so.zero > 1000, "too few exactly coplanar tuples: %ld", so.zero);
    TEST_CHECK(so.wide_used > 1000, "60-bit integer form barely used: %ld", so.wide_used);
    TEST_CHECK(so.int_used > 1000 && so.exp_used > 1000, "stages not exercised");
    TEST_CHECK(so.zero_bound_wrong > 0, "the static pre-check is not live (a zero bound never erred)");
}

/* Lattice points on integer spheres, translated, scaled by 2^k, moved by ulps. */
static void test_ulp_neighbours_of_cospherical_points_match_oracle(void)
{
    static const int64_t radii2[] = {3, 11, 50, 77, 101, 425, 1001, 16900, 1L << 20};
    static int64_t lat[4096][3];
    tu_rng r = {4};
    reset();
    for (size_t ri = 0; ri < sizeof radii2 / sizeof radii2[0]; ri++) {
        int n = pg_sphere_lattice(radii2[ri], lat, 4096);
        TEST_REQUIRE(n >= 5, "sphere %ld has %d lattice points", (long)radii2[ri], n);
        for (int t = 0; t < 2000; t++) {
            int64_t cen[3];
            int64_t cm = (int64_t)1 << (tu_below(&r, 4) * 12);
            for (int j = 0; j < 3; j++) cen[j] = pg_int(&r, cm);
            int k = (t % 3 == 0) ? 0 : -1070 + (int)tu_below(&r, 2030); /* |coord| < 2^38 */
            double p[5][3];
            for (int i = 0; i < 5; i++) {
                const int64_t *l = lat[tu_below(&r, (uint64_t)n)];
                for (int j = 0; j < 3; j++) p[i][j] = ldexp((double)(l[j] + cen[j]), k);
            }
            if (t % 2) pg_perturb(&r, p, 5);
            check_both(p);
        }
    }
    report("cospherical lattice + ulps");
    TEST_CHECK(si.zero > 3000, "too few exactly co-spherical tuples: %ld", si.zero);
    TEST_CHECK(si.int_used > 1500 && si.exp_used > 3000, "stages not exercised");
    TEST_CHECK(si.zero_bound_wrong > 0, "the static pre-check is not live (a zero bound never erred)");
}

/* Integer grids of several sizes, around the int64 / __int128 / expansion boundaries. */
static void test_integer_grids_match_oracle(void)
{
    static const int bits[] = {1, 2, 5, 10, 11, 12, 20, 21, 22, 23, 24, 30, 39, 40, 41, 45, 53};
    tu_rng r = {5};
    reset();
    for (size_t bi = 0; bi < sizeof bits / sizeof bits[0]; bi++) {
        int64_t m = ((int64_t)1 << bits[bi]) - 1;
        for (int t = 0; t < 2000; t++) {
            double p[5][3];
            for (int i = 0; i < 5; i++)
                for (int j = 0; j < 3; j++) {
                    /* near the top of the range or anywhere in it; few distinct values on
                     * the small grids so that degeneracies are frequent */
                    int64_t v = (t & 1) ? m - (int64_t)tu_below(&r, 4) : pg_int(&r, m);
                    p[i][j] = (double)((tu_next(&r) & 1) ? v : -v);
                }
            check_both(p);
        }
    }
    report("integer grids");
    TEST_CHECK(so.zero > 500 && si.zero > 500, "grids gave too few zeros");
}

/* Points rounded onto a sphere: centre + radius * unit direction, rounded to doubles. */
static void test_points_rounded_onto_a_sphere_match_oracle(void)
{
    tu_rng r = {6};
    reset();
    for (int t = 0; t < 10000; t++) {
        double cen[3], rad = ldexp(1.0 + tu_uniform(&r), (int)pg_int(&r, 30));
        for (int j = 0; j < 3; j++) cen[j] = (tu_uniform(&r) - 0.5) * ldexp(1.0, (int)tu_below(&r, 20));
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            double v[3], n2;
            do {
                for (int j = 0; j < 3; j++) v[j] = 2 * tu_uniform(&r) - 1;
                n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            } while (n2 < 0.01 || n2 > 1);
            double inv = rad / sqrt(n2);
            for (int j = 0; j < 3; j++) p[i][j] = cen[j] + v[j] * inv;
        }
        check_insphere(p);
        if (t % 4 == 0) check_orient(p);
    }
    report("rounded onto a sphere");
    TEST_CHECK(si.filter_decided < si.tuples, "sphere points never reached the exact stage");
    TEST_CHECK(si.wide_used > si.tuples / 2, "60-bit integer form barely used: %ld", si.wide_used);
    TEST_CHECK(si.wide122_used > si.wide_used, "the 122-bit form refused a 60-bit tuple");
}

/* Subnormals, 2^-1074, 2^1000, near DBL_MAX and mixtures. */
static void test_extreme_magnitudes_match_oracle(void)
{
    static const double vals[] = {0.0, 0x1p-1074, 0x3p-1074, 0x1p-1073, 0x1p-1022,
                                  0x0.fffffffffffffp-1022, 0x1p-1000, 0x1.8p-600, 1.0, 1.5,
                                  0x1p500, 0x1p1000, 0x1.cp1000, 0x1.fffffffffffffp1023,
                                  0x1p1020, 3.0, 0x1p-150, 0x1p150};
    const int nv = (int)(sizeof vals / sizeof vals[0]);
    tu_rng r = {7};
    reset();
    for (int t = 0; t < 12000; t++) {
        double p[5][3];
        int mode = t % 4;
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) {
                double v = vals[tu_below(&r, (uint64_t)nv)];
                if (mode == 1) v = ldexp((double)pg_int(&r, 3), -1074);        /* denormal grid */
                if (mode == 2) v = ldexp((double)pg_int(&r, 3), 960);          /* huge grid */
                if (mode == 3 && (i & 1)) v = ldexp((double)pg_int(&r, 3), -1074);
                if (mode == 3 && !(i & 1)) v = ldexp((double)pg_int(&r, 3), 1000);
                p[i][j] = (tu_next(&r) & 1) ? -v : v;
            }
        if (t % 5 == 0) pg_perturb(&r, p, 5);
        check_both(p);
    }
    report("extreme magnitudes");
    TEST_CHECK(so.zero > 120 && si.zero > 120, "too few zeros among extreme tuples");
}

/* Lattice exactness (pred_static, proofs/filters.md section 9).  Tuples of a lattice 2^s Z^3
 * (plus an offset on the lattice) whose extents are at most E units: pred_static_init must
 * call the filters exact exactly within the proved limits, and then the filter with the
 * static bound 0 must give the oracle's sign, 0 included.  Coordinates are drawn from
 * {0, 1, E-1, E} and uniform [0, E] so that the intermediates reach their bounds.  Returns the
 * number of tuples where the filter's answer differs from the oracle's. */
static long lattice_mismatches(int insphere, long E, int s, int tuples, uint64_t seed,
                               int expect_exact)
{
    tu_rng r = {seed};
    long bad = 0;
    for (int t = 0; t < tuples; t++) {
        double p[7][3];  /* 5 tuple points and two corners fixing the extents at E */
        const double off = ldexp((double)tu_below(&r, (uint64_t)1 << 30), s);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) {
                const uint64_t k = tu_below(&r, 8);
                const long v = k == 0 ? 0 : k == 1 ? 1 : k == 2 ? E - 1 : k == 3 ? E
                                                 : (long)tu_below(&r, (uint64_t)E + 1);
                p[i][j] = off + ldexp((double)v, s);
            }
        for (int j = 0; j < 3; j++) {
            p[5][j] = off;
            p[6][j] = off + ldexp((double)E, s);
        }
        pred_static ps;
        pred_static_init(&p[0][0], 3, 7, &ps);
        const int exact = insphere ? ps.is_exact : ps.o3_exact;
        if (exact != expect_exact) {
            TEST_CHECK(0, "E=%ld s=%d: pred_static_init says %s", E, s, exact ? "exact" : "not exact");
            return -1;
        }
        const int ref = insphere ? orc_insphere(p[0], p[1], p[2], p[3], p[4])
                                 : orc_orient3d(p[0], p[1], p[2], p[3]);
        const int f = insphere ? pred_insphere_filter(p[0], p[1], p[2], p[3], p[4], 0.0, NULL)
                               : pred_orient3d_filter(p[0], p[1], p[2], p[3], 0.0);
        bad += f != ref;
    }
    return bad;
}

static void test_lattice_filters_are_exact_within_the_proved_extents(void)
{
    static const int scales[] = {-214, -100, -1, 0, 7, 194};
    for (size_t k = 0; k < sizeof scales / sizeof *scales; k++) {
        const int s = scales[k];
        long b = lattice_mismatches(1, (long)PRED_IS_LATTICE_E, s, 20000, 11 + k, 1);
        TEST_CHECK(b == 0, "insphere, E=%ld, s=%d: %ld tuples differ from the oracle",
                   (long)PRED_IS_LATTICE_E, s, b);
        {
            b = lattice_mismatches(0, (long)PRED_O3_LATTICE_E, s, 20000, 31 + k, 1);
            TEST_CHECK(b == 0, "orient3d, E=%ld, s=%d: %ld tuples differ from the oracle",
                       (long)PRED_O3_LATTICE_E, s, b);
        }
    }
    /* just past the limits, or outside the exponent range: not exact */
    TEST_CHECK(lattice_mismatches(1, (long)PRED_IS_LATTICE_E + 1, 0, 10, 5, 0) >= 0, "E+1");
    TEST_CHECK(lattice_mismatches(0, (long)PRED_O3_LATTICE_E + 1, 0, 10, 6, 0) >= 0, "E+1");
    TEST_CHECK(lattice_mismatches(1, 100, -215, 10, 7, 0) >= 0, "s = -215");
    TEST_CHECK(lattice_mismatches(1, 100, 195, 10, 8, 0) >= 0, "s = 195");
    /* the limits are not vacuous: far past them a zero static bound gives wrong answers */
    const long far = lattice_mismatches(1, 1L << 20, 0, 20000, 9, 0);
    TEST_CHECK(far > 0, "insphere on a 2^20 lattice never erred with a zero bound");
    pred_static ps;
    double q[2][3] = {{0.1, 0.2, 0.3}, {0.7, 0.5, 0.9}};
    pred_static_init(&q[0][0], 3, 2, &ps);
    TEST_CHECK(!ps.is_exact && !ps.o3_exact && ps.is_seps > 0 && ps.o3_seps > 0,
               "non-lattice doubles called exact");
}

/* Axis-aligned planes (src/pred/orient3d.c, insphere.c: the axis-plane rules; exact_int.c:
 * the coplanar predicates on the wide integer form): three (orient3d) or four (insphere) of the
 * points share one coordinate value exactly, the others are anywhere, the off-plane offset
 * down to 2^-1074 (a plane and a subnormal apex: too many binades for the integer forms of
 * the whole tuple).  In-plane coordinates are random doubles, or small integers times 2^-20
 * (co-circular and collinear cases: exact zeros), so every sign and both zero cases occur.
 * Every position of the off-plane point and every axis.  The ghost rule and the coplanar
 * orientation on the in-plane points (orient2d / lifted2d on non-integer doubles) are checked
 * too. */
static void test_axis_aligned_planes_match_oracle(void)
{
    reset();
    tu_rng r = {2027};
    const double planes[] = {0.0, 0.75, -3.0e5, 0x1p-1000};
    const double offs[] = {1.0, -0.5, 0x1p-1074, -0x1p-1060, 1e-300, 3.0e5};
    long bad2 = 0, n2 = 0;
    for (int t = 0; t < 24000; t++) {
        const int j = t % 3, off = (t / 3) % 5;
        const double P = planes[(t / 15) % 4];
        const int integer = (t / 60) % 2;
        double q[5][3];
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < 3; k++)
                q[i][k] = integer ? (double)((int)tu_below(&r, 5) - 2) * 0x1p-20 : tu_uniform(&r);
        for (int i = 0; i < 5; i++) q[i][j] = P;
        q[off][j] = P + offs[tu_below(&r, 6)];
        if (q[off][j] == P) q[off][j] = P + 1;  /* the offset was absorbed by rounding */
        check_both(q);
        /* the four in-plane points: coplanar orientation, ghost rule */
        const double *in[4];
        for (int i = 0, k = 0; i < 5; i++)
            if (i != off) in[k++] = q[i];
        gtet_pred_counters cnt;
        memset(&cnt, 0, sizeof cnt);
        int ok = pred_coplanar_orientation(in[0], in[1], in[2], &cnt) ==
                 orc_coplanar_orientation(in[0], in[1], in[2]);
        if (orc_coplanar_orientation(in[0], in[1], in[2]) != 0)
            ok &= pred_ghost_conflict(in[0], in[1], in[2], in[3], &cnt) ==
                  orc_ghost_conflict(in[0], in[1], in[2], in[3]);
        n2++;
        if (!ok && bad2++ < 5) TEST_CHECK(0, "coplanar predicate mismatch on plane %d, tuple %d", j, t);
    }
    report("axis-aligned planes");
    TEST_CHECK(so.bad == 0 && si.bad == 0, "%ld orient3d / %ld insphere mismatches", so.bad, si.bad);
    TEST_CHECK(bad2 == 0, "%ld of %ld coplanar mismatches", bad2, n2);
    TEST_CHECK(so.zero > 1000 && si.zero > 1000, "too few exact zeros (%ld, %ld)", so.zero, si.zero);
}

/* The 60-bit integer form at its limits (exact_int.c: the fast conversion and the radix-2^62
 * columns of pred_insphere_wide).  Integers below 2^60 (the form's bound) that are doubles,
 * drawn from the extremes +-(2^53 - 1) 2^7 (the largest below 2^60), +-2^59, +-1, 0 and
 * 53-bit random integers shifted by 0-7 bits, times 2^k for k from the
 * subnormal range to 2^900 (the scale must not matter): every intermediate reaches its proved
 * bound.  Co-spherical lattice points scaled to ~2^58 give exact zeros and +-1-unit neighbours
 * at full width.  A tuple spanning 60 bits must be accepted by the form, one of 61 rejected. */
static void test_wide_integer_form_at_its_limits_match_oracle(void)
{
    static int64_t lat[512][3];
    const int64_t top = (((int64_t)1 << 53) - 1) << 7;  /* the largest double below 2^60 */
    const int64_t picks[] = {top, -top, (int64_t)1 << 59, -((int64_t)1 << 59), 1, -1, 0};
    tu_rng r = {2028};
    reset();
    const int nl = pg_sphere_lattice(16900, lat, 512);
    TEST_REQUIRE(nl >= 5, "lattice sphere has %d points", nl);
    for (int t = 0; t < 12000; t++) {
        const int k = t % 4 == 0 ? 0 : -1074 + (int)tu_below(&r, 1974);  /* 2^60 * 2^k finite */
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            const int64_t *l = lat[tu_below(&r, (uint64_t)nl)];
            for (int j = 0; j < 3; j++) {
                int64_t v;
                if (t % 3 == 2) { /* lattice sphere * 2^43 (< 2^58), moved by 0 or +-1 unit */
                    v = l[j] * ((int64_t)1 << 43) + (tu_below(&r, 8) == 0 ? pg_int(&r, 1) : 0);
                } else {
                    const uint64_t w = tu_below(&r, 10);
                    /* a multiplication, not a shift: the value may be negative */
                    v = w < 7 ? picks[w]
                              : pg_int(&r, ((int64_t)1 << 53) - 1) *
                                    ((int64_t)1 << tu_below(&r, 8));
                }
                p[i][j] = ldexp((double)v, k);
            }
        }
        check_insphere(p);
        if (t % 2 == 0) check_orient(p);
    }
    report("60-bit integer form limits");
    TEST_CHECK(si.wide_used == si.tuples, "the form refused %ld of %ld tuples of integers below 2^60",
               si.tuples - si.wide_used, si.tuples);
    TEST_CHECK(si.zero > 100, "too few zeros at full width: %ld", si.zero);
    /* 60 bits of span accepted, 61 refused, at two scales */
    for (int k = -1000; k <= 900; k += 1900) {
        double q[5][3] = {{0x1p59, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0.5, 0.5, 0.5}};
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) q[i][j] = ldexp(q[i][j] == 0.5 ? 1.0 : q[i][j], k);
        int sgn;
        TEST_CHECK(pred_insphere_wide(q[0], q[1], q[2], q[3], q[4], &sgn) &&
                       sgn == orc_insphere(q[0], q[1], q[2], q[3], q[4]),
                   "a 60-bit span refused or wrong at 2^%d", k);
        q[4][0] = ldexp(0.5, k);  /* one bit lower: 61 bits */
        TEST_CHECK(!pred_insphere_wide(q[0], q[1], q[2], q[3], q[4], &sgn),
                   "a 61-bit span accepted at 2^%d", k);
    }
}

/* The 122-bit integer form (exact_int.c: pred_insphere_wide122) on what it exists for and at
 * its limits: (1) points rounded onto a sphere with one coordinate moved near 0 (times 2^-8 ..
 * 2^-60: the tuple spans 61-122 binades, the 60-bit form refuses it), (2) integers up to the
 * largest double below 2^122, (2^53 - 1) 2^69, from the extremes and 53-bit random integers
 * shifted by 0-69 bits, at scales 2^-1074 .. 2^850, (3) e equal to one of a..d (exact zeros)
 * in such tuples.  Every answer against the oracle; 122 bits of span accepted, 123 refused. */
static void test_122_bit_integer_form_match_oracle(void)
{
    const int64_t top53 = ((int64_t)1 << 53) - 1;
    tu_rng r = {2029};
    reset();
    long wide_span = 0;
    for (int t = 0; t < 12000; t++) {
        double p[5][3];
        const int mode = t % 3;
        const int k = t % 4 == 0 ? 0 : -1074 + (int)tu_below(&r, 1924);
        for (int i = 0; i < 5; i++) {
            double v[3], n2;
            do {
                for (int j = 0; j < 3; j++) v[j] = 2 * tu_uniform(&r) - 1;
                n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            } while (n2 < 0.01 || n2 > 1);
            for (int j = 0; j < 3; j++) {
                if (mode == 0) {
                    p[i][j] = v[j] / sqrt(n2);
                } else {
                    const uint64_t w = tu_below(&r, 8);
                    const double x = w == 0 ? ldexp((double)top53, 69) : w == 1 ? 0x1p121
                                   : w == 2 ? 1.0 : w == 3 ? 0.0
                                   : ldexp((double)pg_int(&r, top53), (int)tu_below(&r, 70));
                    p[i][j] = ldexp((tu_next(&r) & 1) ? -x : x, k);
                }
            }
        }
        if (mode == 0) {  /* one coordinate near 0 */
            const int i = (int)tu_below(&r, 5), j = (int)tu_below(&r, 3);
            p[i][j] = ldexp(p[i][j], -8 - (int)tu_below(&r, 53));
        }
        if (t % 5 == 0) memcpy(p[4], p[tu_below(&r, 4)], sizeof p[4]);  /* exact zero */
        int s;
        wide_span += !pred_insphere_wide(p[0], p[1], p[2], p[3], p[4], &s);
        check_insphere(p);
    }
    report("122-bit integer form");
    TEST_CHECK(si.bad == 0, "%ld insphere mismatches", si.bad);
    TEST_CHECK(wide_span > 3000, "too few tuples beyond the 60-bit form: %ld", wide_span);
    TEST_CHECK(si.wide122_used == si.tuples, "the 122-bit form refused %ld of %ld tuples",
               si.tuples - si.wide122_used, si.tuples);
    TEST_CHECK(si.zero >= 2400, "too few exact zeros: %ld", si.zero);
    for (int k = -1000; k <= 800; k += 1800) {
        double q[5][3] = {{0x1p121, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {1, 0, 1}};
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) q[i][j] = ldexp(q[i][j], k);
        int sgn;
        TEST_CHECK(pred_insphere_wide122(q[0], q[1], q[2], q[3], q[4], &sgn) &&
                       sgn == orc_insphere(q[0], q[1], q[2], q[3], q[4]),
                   "a 122-bit span refused or wrong at 2^%d", k);
        q[4][0] = ldexp(0.5, k);  /* one bit lower: 123 bits */
        TEST_CHECK(!pred_insphere_wide122(q[0], q[1], q[2], q[3], q[4], &sgn),
                   "a 123-bit span accepted at 2^%d", k);
    }
}

/* A NaN or infinite coordinate anywhere: every public predicate answers 0 and returns (it used
 * to reach GMP's mpz_set_d, whose SIGFPE killed the caller: NOTES.md E160). */
static void test_nonfinite_coordinates_give_0_not_a_crash(void)
{
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int slot = 0; slot < 5; slot++)
        for (int axis = 0; axis < 3; axis++)
            for (int k = 0; k < 3; k++) {
                double p[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.2, 0.2, 0.2}};
                p[slot][axis] = bad[k];
                const int o = gtet_orient3d(p[0], p[1], p[2], p[slot < 4 ? 3 : slot]);
                const int i = gtet_insphere(p[0], p[1], p[2], p[3], p[4]);
                const int s = gtet_insphere_sos(p[0], p[1], p[2], p[3], p[4]);
                const int g = gtet_ghost_conflict(p[0], p[1], p[2], p[slot == 3 ? 3 : 4]);
                TEST_CHECK(o == 0 && i == 0 && s == 0 && g == 0,
                           "point %d axis %d = %g: orient %d insphere %d sos %d ghost %d", slot,
                           axis, bad[k], o, i, s, g);
            }
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, d[3] = {0, 0, 1};
    TEST_CHECK(gtet_orient3d(a, b, c, d) == 1, "finite points still have their sign");
}

int main(void)
{
    TU_RUN(test_random_unit_doubles_match_oracle);
    TU_RUN(test_random_doubles_any_exponent_match_oracle);
    TU_RUN(test_ulp_neighbours_of_coplanar_points_match_oracle);
    TU_RUN(test_ulp_neighbours_of_cospherical_points_match_oracle);
    TU_RUN(test_integer_grids_match_oracle);
    TU_RUN(test_points_rounded_onto_a_sphere_match_oracle);
    TU_RUN(test_extreme_magnitudes_match_oracle);
    TU_RUN(test_lattice_filters_are_exact_within_the_proved_extents);
    TU_RUN(test_axis_aligned_planes_match_oracle);
    TU_RUN(test_wide_integer_form_at_its_limits_match_oracle);
    TU_RUN(test_122_bit_integer_form_match_oracle);
    TU_RUN(test_nonfinite_coordinates_give_0_not_a_crash);
    return tu_finish();
}
