/* test_pred_packed_filter.c -- the kernel's two-lane insphere filters
 * (src/pred/filter_packed.h pred_insphere_filter_packed, static test first, and
 * pred_insphere_filter_packed_sf, semi-static bound first) are the scalar filter bit for bit.
 *
 * Specification: its det~ (pred_insphere_det_packed_) is the bytes of det~ evaluated in
 * filter.h's FIXED order (typed again here; NaN for NaN); on every tuple and every kind of
 * static bound (none, a box's, 0 for a lattice) both packed filters return what
 * pred_insphere_filter returns and leave the same record (compared as bytes) when undecided,
 * and the static-first one counts a static miss exactly when |det~| <= seps (or det~ is NaN).
 * Tuples: uniform in a box, points rounded onto a sphere with a fifth point near it (the
 * record's path), ulp neighbours of lattice points of an integer sphere (exactly co-spherical:
 * seps 0), random doubles of every magnitude (the guards, overflowing translations), and small
 * integers with zeros.  Where SSE2 is not available the kernel uses the scalar filter and there
 * is nothing to compare.
 */
#include "pred/filter.h"
#include "pred_gen.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

#ifdef PRED_INSPHERE_PACKED

static long compared, undecided;

/* det~ in the FIXED evaluation order of filter.h, typed again (the reference) */
static double det_scalar(double (*p)[3])
{
    const double *a = p[0], *b = p[1], *c = p[2], *d = p[3], *e = p[4];
    const double ax = a[0] - e[0], ay = a[1] - e[1], az = a[2] - e[2];
    const double bx = b[0] - e[0], by = b[1] - e[1], bz = b[2] - e[2];
    const double cx = c[0] - e[0], cy = c[1] - e[1], cz = c[2] - e[2];
    const double dx = d[0] - e[0], dy = d[1] - e[1], dz = d[2] - e[2];
    const double ab = ax * by - bx * ay;
    const double bc = bx * cy - cx * by;
    const double cd = cx * dy - dx * cy;
    const double da = dx * ay - ax * dy;
    const double ac = ax * cy - cx * ay;
    const double bd = bx * dy - dx * by;
    const double abc = (az * bc - bz * ac) + cz * ab;
    const double bcd = (bz * cd - cz * bd) + dz * bc;
    const double cda = (cz * da + dz * ac) + az * cd;
    const double dab = (dz * ab + az * bd) + bz * da;
    const double aw = (ax * ax + ay * ay) + az * az;
    const double bw = (bx * bx + by * by) + bz * bz;
    const double cw = (cx * cx + cy * cy) + cz * cz;
    const double dw = (dx * dx + dy * dy) + dz * dz;
    return (cw * dab - dw * abc) + (aw * bcd - bw * cda);
}

#ifdef PRED_INSPHERE_PACKED4
static long level_decided;

/* The level filter (pred_insphere_filter_packed_lv) on the tuple for levels w around its
 * largest translated coordinate (2^-3 .. 2^3 times the power of two above it) and none (w 0):
 * where the scalar filter decides it gives the same sign; where it returns 0 it leaves the
 * scalar's record and counts a miss, and the level moves to the power of two above the
 * tuple's largest coordinate; it decides a call the scalar leaves only for a tuple whose maxima
 * fail the scalar's guard (a unit below PRED_IS_LO: section 8 needs only the level's units).
 * A level whose bound were not section 8's (sw of 2w for w) would give wrong signs on the
 * near-co-spherical tuples. */
static void compare_levels(double (*p)[3], double seps, int s, const double *ms)
{
    double X = 0, Y = 0, Z = 0;
    for (int i = 0; i < 4; i++) {
        X = fmax(X, fabs(p[i][0] - p[4][0]));
        Y = fmax(Y, fabs(p[i][1] - p[4][1]));
        Z = fmax(Z, fabs(p[i][2] - p[4][2]));
    }
    const double M = fmax(fmax(X, Y), Z), lo = fmin(fmin(X, Y), Z);
    if (!(M > 0 && M < PRED_IS_HI)) return;
    const double top = pred_pow2_above_(M);
    for (int k = -4; k <= 3; k++) {
        pred_is_level lv = {0.0, 0.0};
        if (k > -4) {
            lv.w = ldexp(top, k);
            lv.sw = pred_min_(pred_insphere_static_eps(lv.w, lv.w, lv.w), seps);
        }
        double ml[PRED_IS_NMINORS];
        memset(ml, 0x5a, sizeof ml);
        uint64_t misses = 0;
        const int l = pred_insphere_filter_packed_lv(p[0], p[1], p[2], p[3], p[4], seps, &lv,
                                                     ml, &misses);
        level_decided += l != 0;
        if (s != 0) {
            TEST_CHECK(l == s, "level 2^%d of the top: %d against the scalar's %d (seps %a)", k,
                       l, s, seps);
        } else if (l != 0) {
            TEST_CHECK(!(lo >= PRED_IS_LO), "level 2^%d decides %d where the scalar does not, "
                       "with maxima %a %a %a", k, l, X, Y, Z);
        } else {
            TEST_CHECK(memcmp(ms, ml, sizeof ml) == 0, "level 2^%d: another record", k);
        }
        if (l == 0) {
            TEST_CHECK(misses == 1 && lv.w == top,
                       "level 2^%d undecided: %llu misses, level moved to %a (top %a)", k,
                       (unsigned long long)misses, lv.w, top);
        }
    }
}
#endif

static void compare(double (*p)[3], double seps)
{
    double ms[PRED_IS_NMINORS], mp[PRED_IS_NMINORS], mf[PRED_IS_NMINORS];
    memset(ms, 0x5a, sizeof ms);
    memset(mp, 0x5a, sizeof mp);
    memset(mf, 0x5a, sizeof mf);
    uint64_t misses = 0;
    const int s = pred_insphere_filter(p[0], p[1], p[2], p[3], p[4], seps, ms);
    const int k = pred_insphere_filter_packed(p[0], p[1], p[2], p[3], p[4], seps, mp, &misses);
    const int f = pred_insphere_filter_packed_sf(p[0], p[1], p[2], p[3], p[4], seps, mf);
    const double ds = det_scalar(p), dp = pred_insphere_det_packed_(p[0], p[1], p[2], p[3], p[4]);
#ifdef PRED_INSPHERE_PACKED4
    compare_levels(p, seps, s, ms);
#endif
    compared++;
    undecided += s == 0;
    TEST_CHECK(memcmp(&ds, &dp, sizeof ds) == 0 || (isnan(ds) && isnan(dp)),
               "det~ scalar %a packed %a", ds, dp);
    /* the static test's misses: exactly the calls it leaves, |det~| <= seps or NaN */
    TEST_CHECK(misses == (uint64_t)!(ds > seps || ds < -seps), "misses %llu, det~ %a seps %a",
               (unsigned long long)misses, ds, seps);
    if (s != k || memcmp(ms, mp, sizeof ms) != 0 || s != f || memcmp(ms, mf, sizeof ms) != 0) {
        TEST_CHECK(0, "scalar %d packed %d semi-first %d (seps %a) at (%a %a %a) (%a %a %a) "
                   "(%a %a %a) (%a %a %a) (%a %a %a); records %a %a %a %a %a %a / %a %a %a %a "
                   "%a %a / %a %a %a %a %a %a", s, k, f,
                   seps, p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2], p[2][0], p[2][1],
                   p[2][2], p[3][0], p[3][1], p[3][2], p[4][0], p[4][1], p[4][2], ms[0], ms[1],
                   ms[2], ms[3], ms[4], ms[5], mp[0], mp[1], mp[2], mp[3], mp[4], mp[5], mf[0],
                   mf[1], mf[2], mf[3], mf[4], mf[5]);
    }
}


#ifdef PRED_ORIENT3D_FACETS4
static long facet_lanes, facet_undecided;

/* the walk's four orient3d lanes (tet p[0..3], point p[4]) against the scalar filter, lane by
 * lane */
static void compare_facets(double (*p)[3], double seps)
{
    unsigned neg = 0xf0, und = 0xf0;
    pred_orient3d_facets4_(p[0], p[1], p[2], p[3], p[4], seps, &neg, &und);
    TEST_CHECK(neg < 16 && und < 16 && (neg & und) == 0, "masks neg %x und %x", neg, und);
    for (int f = 0; f < 4; f++) {
        const double *q[4] = {p[0], p[1], p[2], p[3]};
        q[f] = p[4];
        const int s = pred_orient3d_filter(q[0], q[1], q[2], q[3], seps);
        const int k = (neg >> f & 1) ? -1 : (und >> f & 1) ? 0 : 1;
        facet_lanes++;
        facet_undecided += s == 0;
        TEST_CHECK(s == k, "facet %d: scalar %d lanes %d (seps %a) at (%a %a %a) (%a %a %a) "
                   "(%a %a %a) (%a %a %a) p (%a %a %a)", f, s, k, seps, p[0][0], p[0][1],
                   p[0][2], p[1][0], p[1][1], p[1][2], p[2][0], p[2][1], p[2][2], p[3][0],
                   p[3][1], p[3][2], p[4][0], p[4][1], p[4][2]);
    }
}
#endif

/* o3_seps: the orient3d static bound of the same box, for the walk's lanes */
static void compare_all_bounds(double (*p)[3], double box_seps, double o3_seps)
{
    compare(p, PRED_NO_STATIC);
    compare(p, box_seps);
    compare(p, 0.0);
#ifdef PRED_ORIENT3D_FACETS4
    compare_facets(p, PRED_NO_STATIC);
    compare_facets(p, o3_seps);
    compare_facets(p, 0.0);
#else
    (void)o3_seps;
#endif
}

static void test_uniform_tuples_agree(void)
{
    tu_rng r = {1};
    const double seps = pred_insphere_static_eps(1.0, 1.0, 1.0);
    for (int n = 0; n < 200000; n++) {
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = tu_uniform(&r);
        compare_all_bounds(p, seps, pred_orient3d_static_eps(1.0, 1.0, 1.0));
    }
}

static void test_near_cospherical_tuples_agree(void)
{
    /* rounded onto the unit sphere: the static bound and often the semi-static one fail, so
     * the record is compared too */
    tu_rng r = {2};
    const double seps = pred_insphere_static_eps(2.0, 2.0, 2.0);
    long before = undecided;
    for (int n = 0; n < 100000; n++) {
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            double v[3], q = 0;
            for (int j = 0; j < 3; j++) {
                v[j] = 2 * tu_uniform(&r) - 1;
                q += v[j] * v[j];
            }
            q = sqrt(q);
            for (int j = 0; j < 3; j++) p[i][j] = v[j] / q;
        }
        if (n & 1) pg_perturb(&r, p, 5);
        compare_all_bounds(p, seps, pred_orient3d_static_eps(2.0, 2.0, 2.0));
    }
    TEST_CHECK(undecided - before > 1000, "only %ld undecided: the record was hardly compared",
               undecided - before);
}

static void test_lattice_sphere_neighbours_agree(void)
{
    static int64_t pts[4096][3];
    const int n = pg_sphere_lattice(5 * 5 * 13 * 13, pts, 4096);
    TEST_REQUIRE(n >= 5, "sphere lattice: %d points", n);
    tu_rng r = {3};
    const double seps = pred_insphere_static_eps(130.0, 130.0, 130.0);
    for (int t = 0; t < 50000; t++) {
        double p[5][3];
        for (int i = 0; i < 5; i++) {
            const int k = (int)tu_below(&r, (uint64_t)n);
            for (int j = 0; j < 3; j++) p[i][j] = (double)pts[k][j];
        }
        if (t % 3 == 0) pg_perturb(&r, p, 5);
        compare_all_bounds(p, seps, pred_orient3d_static_eps(130.0, 130.0, 130.0));
    }
}

static void test_every_magnitude_agrees(void)
{
    /* subnormals to DBL_MAX: the guards' paths, infinite and NaN translations */
    tu_rng r = {4};
    for (int t = 0; t < 100000; t++) {
        double p[5][3];
        const int lo = (int)tu_below(&r, 2038) - 1074, hi = lo + (int)tu_below(&r, 60);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = pg_double_exp(&r, lo, hi);
        const double w = ldexp(1.0, hi + 1);
        compare_all_bounds(p, pred_insphere_static_eps(w, w, w), pred_orient3d_static_eps(w, w, w));
    }
}

static void test_small_integers_with_zeros_agree(void)
{
    tu_rng r = {5};
    for (int t = 0; t < 100000; t++) {
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = (double)pg_int(&r, 2);
        compare_all_bounds(p, pred_insphere_static_eps(4.0, 4.0, 4.0),
                           pred_orient3d_static_eps(4.0, 4.0, 4.0));
    }
}

static void test_points_near_a_facet_agree(void)
{
    /* the walk's point on or next to a facet's plane (a rounded barycentric combination of
     * three vertices, moved by a few ulps): the static and semi-static tests fail there */
    tu_rng r = {6};
    const double seps = pred_insphere_static_eps(1.0, 1.0, 1.0);
    const double o3 = pred_orient3d_static_eps(1.0, 1.0, 1.0);
    for (int t = 0; t < 100000; t++) {
        double p[5][3];
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 3; j++) p[i][j] = tu_uniform(&r);
        const int f = (int)tu_below(&r, 4);
        double w[3] = {tu_uniform(&r), tu_uniform(&r), 0};
        w[2] = 1 - w[0] - w[1];
        for (int j = 0; j < 3; j++) {
            double x = 0;
            for (int i = 0, k = 0; i < 4; i++)
                if (i != f) x += w[k++] * p[i][j];
            p[4][j] = x;
        }
        if (t & 1) pg_perturb(&r, p + 4, 1);
        compare_all_bounds(p, seps, o3);
    }
#ifdef PRED_ORIENT3D_FACETS4
    TEST_CHECK(facet_undecided > 1000, "only %ld undecided lanes: the rest was hardly compared",
               facet_undecided);
#endif
}

int main(void)
{
    TU_RUN(test_uniform_tuples_agree);
    TU_RUN(test_near_cospherical_tuples_agree);
    TU_RUN(test_lattice_sphere_neighbours_agree);
    TU_RUN(test_every_magnitude_agrees);
    TU_RUN(test_small_integers_with_zeros_agree);
    TU_RUN(test_points_near_a_facet_agree);
#ifdef PRED_ORIENT3D_FACETS4
    printf("walk's lanes: %ld compared, %ld undecided\n", facet_lanes, facet_undecided);
#endif
    printf("%ld comparisons, %ld undecided\n", compared, undecided);
#ifdef PRED_INSPHERE_PACKED4
    printf("level filter: %ld of its calls decided\n", level_decided);
#endif
    return tu_finish();
}

#else

int main(void)
{
    printf("no packed filter on this target: the kernel uses the scalar one\n");
    return 0;
}

#endif
