/* test_pred_perturbation.c -- the symbolic perturbation (insphere_sos, ghost rule, perturbed
 * coplanar in-circle) follows CGAL's rule and has the properties the kernel relies on.
 *
 * Specifications tested:
 *   - hand-checked cases on the unit cube (worked out in the comments below);
 *   - on every 5-subset of the cube's 8 corners, in every order of (a,b,c,d) and every choice
 *     of e: insphere_sos is never 0 when orient3d(a,b,c,d) != 0, equals the exact insphere when
 *     that is non-zero, changes sign under odd permutations of (a,b,c,d), and equals the
 *     independent oracle orc_insphere_sos;
 *   - the same on random 5-tuples of lattice points of integer spheres and of a 3^3 grid,
 *     at integer, scaled (expansion) and 2^-1074 / 2^960 scales (GMP);
 *   - ghost rule: never 0 for a non-collinear facet and a distinct e, equals orient3d(a,b,c,e)
 *     when that is non-zero, equals the perturbed coplanar in-circle otherwise, which equals
 *     the exact in-circle sign when that is non-zero (checked against a plain 2D in-circle on
 *     planes z = const), and matches orc_ghost_conflict, on planes that need each projection;
 *   - the lattice path (perturbation from the filter's minors) and the integer path (from the
 *     small-integer stage's minors, pred_static.int23) answer as the general rule;
 *   - on small integers the filter's record, where it claims an exact evaluation, agrees with
 *     the integer stage (sign and minors), inside and across the bound PRED_IS_INT_EXACT;
 *   - the ranking of small integers by an integer key at the ends of their range.
 */
#include "oracle/oracle.h"
#include "pred/pred_internal.h"
#include "pred_gen.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

static gtet_pred_counters cnt;

static const double cube[8][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0, 1, 1},
                                  {1, 0, 0}, {1, 0, 1}, {1, 1, 0}, {1, 1, 1}};

/* Worked by hand with CGAL's rule (lexicographic order of corners = index order above). */
/* Exercises proofs/perturbation.md P1. */
static void test_insphere_sos_hand_checked_cube_cases(void)
{
    const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    const double xyz[3] = {1, 1, 1}, xy[3] = {1, 1, 0}, ctr[3] = {0.5, 0.5, 0.5};
    /* centre strictly inside the cube's sphere: exact +1 for the positive (o,x,y,z) */
    TEST_CHECK(pred_orient3d(o, x, y, z, &cnt) == 1, "(o,x,y,z) positive");
    TEST_CHECK(pred_insphere_sos(o, x, y, z, ctr, &cnt) == 1, "centre inside");
    TEST_CHECK(pred_insphere_sos(x, o, y, z, ctr, &cnt) == -1, "centre, swapped tet");
    /* e = (1,1,1) is the highest of {o,z,y,x,e}: outside, -1 */
    TEST_CHECK(pred_insphere(o, x, y, z, xyz, &cnt) == 0, "co-spherical");
    TEST_CHECK(pred_insphere_sos(o, x, y, z, xyz, &cnt) == -1, "e highest -> -1");
    TEST_CHECK(pred_insphere_sos(x, o, y, z, xyz, &cnt) == 1, "e highest, negative tet -> +1");
    /* (o,x,y,xyz) is positive; e = z: highest is d = (1,1,1) -> orient(o,x,y,z) = +1 */
    TEST_CHECK(pred_orient3d(o, x, y, xyz, &cnt) == 1, "(o,x,y,xyz) positive");
    TEST_CHECK(pred_insphere_sos(o, x, y, xyz, z, &cnt) == 1, "d highest -> orient(o,x,y,e)");
    /* e = (1,1,0): highest d gives orient(o,x,y,e) = 0 (z = 0 plane); next is e -> -1 */
    TEST_CHECK(pred_insphere_sos(o, x, y, xyz, xy, &cnt) == -1, "second step: e -> -1");
    /* (o,xy,y,xyz) positive, e = x: highest d -> orient(o,xy,y,x) = 0; next b = (1,1,0)
     * -> orient(o,x,y,xyz) = +1 */
    TEST_CHECK(pred_orient3d(o, xy, y, xyz, &cnt) == 1, "(o,xy,y,xyz) positive");
    TEST_CHECK(pred_insphere_sos(o, xy, y, xyz, x, &cnt) == 1, "second step: b -> +1");
}

static const int perm4[24][4] = {
    {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {0, 3, 2, 1},
    {1, 0, 2, 3}, {1, 0, 3, 2}, {1, 2, 0, 3}, {1, 2, 3, 0}, {1, 3, 0, 2}, {1, 3, 2, 0},
    {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 1, 0, 3}, {2, 1, 3, 0}, {2, 3, 0, 1}, {2, 3, 1, 0},
    {3, 0, 1, 2}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 1, 2, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

static int parity(const int *p)
{
    int inv = 0;
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) inv += p[i] > p[j];
    return (inv & 1) ? -1 : 1;
}

/* All properties on one 5-tuple (e = q[4]) over the 24 orders of (a,b,c,d); returns the
 * number of failures (reported once). */
static int check_sos_tuple(const double (*q)[3])
{
    int base = 0, bad = 0;
    const double *e = q[4];
    if (pred_orient3d(q[0], q[1], q[2], q[3], &cnt) == 0) return 0; /* precondition */
    for (int k = 0; k < 24; k++) {
        const int *p = perm4[k];
        const double *a = q[p[0]], *b = q[p[1]], *c = q[p[2]], *d = q[p[3]];
        int s = pred_insphere_sos(a, b, c, d, e, &cnt);
        int exact = orc_insphere(a, b, c, d, e);
        if (k == 0) base = s;
        if (s == 0) bad++;
        if (exact != 0 && s != exact) bad++;
        if (s != parity(p) * base) bad++;
        if (s != orc_insphere_sos(a, b, c, d, e)) bad++;
    }
    if (bad)
        TEST_CHECK(0, "sos properties fail on (%g %g %g) (%g %g %g) (%g %g %g) (%g %g %g) e (%g %g %g)",
                   q[0][0], q[0][1], q[0][2], q[1][0], q[1][1], q[1][2], q[2][0], q[2][1],
                   q[2][2], q[3][0], q[3][1], q[3][2], e[0], e[1], e[2]);
    return bad;
}

/* Exercises proofs/perturbation.md P2. */
static void test_insphere_sos_on_all_5_subsets_of_cube_corners(void)
{
    int tuples = 0;
    for (int m = 0; m < 256; m++) {
        if (__builtin_popcount((unsigned)m) != 5) continue;
        int idx[5], n = 0;
        for (int i = 0; i < 8; i++)
            if (m & (1 << i)) idx[n++] = i;
        for (int ei = 0; ei < 5; ei++) {
            double q[5][3];
            for (int i = 0, r = 0; i < 5; i++)
                if (i != ei) memcpy(q[r++], cube[idx[i]], sizeof q[0]);
            memcpy(q[4], cube[idx[ei]], sizeof q[0]);
            check_sos_tuple((const double (*)[3])q);
            tuples++;
        }
    }
    TEST_CHECK(tuples == 56 * 5, "tuples %d", tuples);
}

/* Exercises proofs/perturbation.md P2. */
static void test_insphere_sos_on_cospherical_lattice_points_and_small_grid(void)
{
    static int64_t lat[2048][3];
    tu_rng r = {11};
    int n = pg_sphere_lattice(425, lat, 2048);
    TEST_REQUIRE(n > 50, "lattice points %d", n);
    static const int scales[] = {0, -7, 33, -1074, 960};
    int decided_by_sos = 0;
    for (int t = 0; t < 2000; t++) {
        double q[5][3];
        int k = scales[t % 5], grid = (t / 5) % 2;
        int ok = 1;
        for (int i = 0; i < 5; i++) {
            for (int j = 0; j < 3; j++)
                q[i][j] = grid ? ldexp((double)tu_below(&r, 3), k)
                               : ldexp((double)lat[tu_below(&r, (uint64_t)n)][j], k);
            for (int l = 0; l < i; l++)
                if (pred_lex_cmp(q[l], q[i]) == 0) ok = 0; /* distinct points only */
        }
        if (!ok) continue;
        if (!grid) /* whole lattice points, not mixed coordinates */
            for (int i = 0; i < 5; i++) {
                const int64_t *l = lat[tu_below(&r, (uint64_t)n)];
                for (int j = 0; j < 3; j++) q[i][j] = ldexp((double)l[j], k);
            }
        ok = 1;
        for (int i = 0; i < 5; i++)
            for (int l = 0; l < i; l++)
                if (pred_lex_cmp(q[l], q[i]) == 0) ok = 0;
        if (!ok) continue;
        if (orc_insphere(q[0], q[1], q[2], q[3], q[4]) == 0 &&
            orc_orient3d(q[0], q[1], q[2], q[3]) != 0)
            decided_by_sos++;
        if (check_sos_tuple((const double (*)[3])q) > 0) break;
    }
    TEST_CHECK(decided_by_sos > 250, "too few perturbed decisions: %d", decided_by_sos);
    printf("  %d perturbed decisions among the lattice / grid tuples\n", decided_by_sos);
}

/* plain 2D in-circle of (a,b,c,e) in the xy plane, integers: +1 inside for any orientation */
static int incircle_xy(const double *a, const double *b, const double *c, const double *e)
{
    double m[3][3];
    const double *p[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        double dx = p[i][0] - e[0], dy = p[i][1] - e[1];
        m[i][0] = dx, m[i][1] = dy, m[i][2] = dx * dx + dy * dy;
    }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                 m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                 m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
    double o = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    return ((det > 0) - (det < 0)) * ((o > 0) - (o < 0));
}

/* Points of a plane through integer points: z = const (xy projection), x + y = const (yz),
 * y = const (xz: xy and yz projections collinear), a tilted plane x + 2y - 3z = 0. */
static void plane_point(tu_rng *r, int kind, double *p)
{
    int64_t m = (tu_next(r) & 1) ? 1 : 3; /* the 3x3 sub-grid has many collinear triples */
    double s = (double)pg_int(r, m), t = (double)pg_int(r, m);
    switch (kind) {
    case 0: p[0] = s, p[1] = t, p[2] = 2; break;
    case 1: p[0] = s, p[1] = 1 - s, p[2] = t; break;
    case 2: p[0] = s, p[1] = -1, p[2] = t; break;
    default: p[0] = 3 * s - 2 * t, p[1] = t, p[2] = s; break;
    }
}

/* Exercises proofs/perturbation.md P5. */
static void test_ghost_conflict_is_never_zero_and_consistent_with_coplanar_circle(void)
{
    tu_rng r = {12};
    int coplanar = 0, perturbed = 0, bad = 0;
    for (int t = 0; t < 20000 && bad < 5; t++) {
        int kind = t % 4;
        double a[3], b[3], c[3], e[3];
        plane_point(&r, kind, a), plane_point(&r, kind, b), plane_point(&r, kind, c);
        if (t % 3 == 0) /* e off the plane */
            e[0] = (double)pg_int(&r, 3), e[1] = (double)pg_int(&r, 3), e[2] = (double)pg_int(&r, 3);
        else
            plane_point(&r, kind, e);
        if (orc_coplanar_orientation(a, b, c) == 0) continue; /* collinear facet */
        if (!pred_lex_cmp(a, e) || !pred_lex_cmp(b, e) || !pred_lex_cmp(c, e)) continue;
        int g = pred_ghost_conflict(a, b, c, e, &cnt);
        int o = orc_orient3d(a, b, c, e);
        int ok = g != 0 && g == orc_ghost_conflict(a, b, c, e);
        if (o != 0) {
            ok &= g == o;
        } else {
            coplanar++;
            int circ = pred_incircle_coplanar_sos(a, b, c, e, &cnt);
            ok &= g == circ && circ == orc_coplanar_circle_sos(a, b, c, e);
            /* the perturbed circle test is unoriented when the exact one decides */
            int ex = kind == 0 ? incircle_xy(a, b, c, e) : 0;
            if (kind == 0 && ex != 0) ok &= circ == ex;
            if (kind == 0 && ex == 0) perturbed++;
            if (kind == 0 && ex != 0) ok &= pred_incircle_coplanar_sos(b, a, c, e, &cnt) == ex;
        }
        if (!ok && bad++ < 5)
            TEST_CHECK(0, "ghost rule fails: kind %d a (%g %g %g) b (%g %g %g) c (%g %g %g) "
                          "e (%g %g %g): got %d", kind, a[0], a[1], a[2], b[0], b[1], b[2],
                       c[0], c[1], c[2], e[0], e[1], e[2], g);
    }
    TEST_CHECK(coplanar > 5000 && perturbed > 40, "coplanar %d perturbed %d", coplanar,
               perturbed);
}

/* The coplanar in-circle at extreme scales (expansion-free GMP path) equals the oracle. */
/* Exercises proofs/perturbation.md P5. */
static void test_ghost_conflict_at_extreme_scales_matches_oracle(void)
{
    tu_rng r = {13};
    static const int scales[] = {-1074, -1000, -60, 0, 30, 900};
    for (int t = 0; t < 3000; t++) {
        int kind = t % 4, k = scales[tu_below(&r, 6)];
        double p[4][3];
        for (int i = 0; i < 4; i++) {
            plane_point(&r, kind, p[i]);
            for (int j = 0; j < 3; j++) p[i][j] = ldexp(p[i][j], k);
        }
        if (orc_coplanar_orientation(p[0], p[1], p[2]) == 0) continue;
        if (!pred_lex_cmp(p[0], p[3]) || !pred_lex_cmp(p[1], p[3]) || !pred_lex_cmp(p[2], p[3]))
            continue;
        int g = pred_ghost_conflict(p[0], p[1], p[2], p[3], &cnt);
        int want = orc_ghost_conflict(p[0], p[1], p[2], p[3]);
        TEST_REQUIRE(g == want && g != 0, "scale 2^%d kind %d: got %d want %d", k, kind, g, want);
    }
}

/* The five points are distinct and the first four span a tet (counters zeroed first): the
 * tuples the insphere tests below compare, as the kernel only ever asks those. */
static int usable_tuple(double q[5][3], gtet_pred_counters *k_cnt)
{
    for (int i = 0; i < 5; i++)
        for (int k = 0; k < i; k++)
            if (pred_lex_cmp(q[i], q[k]) == 0) return 0;
    memset(k_cnt, 0, sizeof *k_cnt);
    return pred_orient3d(q[0], q[1], q[2], q[3], k_cnt) != 0;
}

/* The lattice path (proofs/filters.md section 9; sos.c orient_from_minors): on a small
 * lattice the kernel decides a zero insphere from the filter's exact minors instead of calling
 * orient3d.  For tuples of a 7^3 grid (many exact zeros, every perturbation step taken) it must
 * answer exactly as the general pred_insphere_sos, in both orientations of (a,b,c,d); and
 * orient_from_minors' five identities are checked against pred_orient3d on the same tuples. */
static void test_lattice_perturbation_from_minors_matches_the_general_rule(void)
{
    tu_rng r = {71};
    pred_static ps;  /* the set: the 7^3 grid {0..6}^3 */
    double box[2][3] = {{0, 0, 0}, {6, 6, 6}};
    pred_static_init(&box[0][0], 3, 2, &ps);
    TEST_REQUIRE(ps.is_exact && ps.o3_exact, "a 7^3 grid is not called exact");
    long zeros = 0, bad = 0;
    for (int t = 0; t < 200000; t++) {
        double q[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) q[i][j] = (double)tu_below(&r, 7);
        gtet_pred_counters k_cnt;
        if (!usable_tuple(q, &k_cnt)) continue;
        double mn[PRED_IS_NMINORS];
        const int f = pred_insphere_filter(q[0], q[1], q[2], q[3], q[4], ps.is_seps, mn);
        const int ref = pred_insphere_sos(q[0], q[1], q[2], q[3], q[4], &k_cnt);
        const int got = f ? f : pred_insphere_sos_rest(q[0], q[1], q[2], q[3], q[4], &ps, mn, &k_cnt);
        bad += got != ref;
        if (f == 0) {
            zeros++;
            /* the identities behind orient_from_minors */
            const double *v[4] = {q[0], q[1], q[2], q[3]};
            const double want[5] = {mn[1], -mn[2], mn[3], -mn[0],
                                    ((mn[1] - mn[2]) + mn[3]) - mn[0]};
            for (int k = 0; k < 5; k++) {
                const double *w[4] = {v[0], v[1], v[2], v[3]};
                if (k < 4) w[k] = q[4];
                const int o = pred_orient3d(w[0], w[1], w[2], w[3], &k_cnt);
                bad += o != (want[k] > 0) - (want[k] < 0);
            }
        }
    }
    TEST_CHECK(zeros > 1000, "only %ld exactly co-spherical tuples", zeros);
    TEST_CHECK(bad == 0, "%ld disagreements between the lattice path and the general rule", bad);
}

/* ps for the widest set of integers below 2^23, (-2^23, 2^23)^3: 1 when it is int23 and not
 * a lattice (the small-integer paths' precondition). */
static int int23_static(pred_static *ps)
{
    const double L = 0x1p23;
    double box[2][3] = {{-L + 1, -L + 1, -L + 1}, {L - 1, L - 1, L - 1}};
    pred_static_init(&box[0][0], 3, 2, ps);
    return ps->int23 && !ps->is_exact;
}

/* The integer path (NOTES.md E30; sos.c pred_insphere_sos_rest_log): on a set of integers below
 * 2^23 (pred_static.int23) too wide for the lattice path, the kernel decides a filtered-out
 * insphere in the small-integer stage without its range checks and, on a zero, reads the
 * perturbation's orient3d signs off that stage's exact minors.  Tuples of 5 corners of boxes
 * (always co-spherical) and of points (x, y, x^2 + y^2) of a paraboloid (many co-spherical
 * 5-tuples), placed anywhere in (-2^23, 2^23)^3: the answer must equal the general
 * pred_insphere_sos in both orientations of (a,b,c,d), the minors must give pred_orient3d's
 * five signs, and int23 must hold exactly for integer sets inside the bound. */
static void test_integer_perturbation_from_minors_matches_the_general_rule(void)
{
    tu_rng r = {23};
    pred_static ps;
    TEST_REQUIRE(int23_static(&ps), "the set (-2^23, 2^23)^3 is not called int23");
    const double L = 0x1p23;
    double out[2][3] = {{0, 0, 0}, {L, 1, 1}};  /* 2^23 itself: outside the bound */
    pred_static po;
    pred_static_init(&out[0][0], 3, 2, &po);
    TEST_CHECK(!po.int23, "a coordinate 2^23 is called int23");
    out[1][0] = 0.5;                           /* not an integer */
    pred_static_init(&out[0][0], 3, 2, &po);
    TEST_CHECK(!po.int23, "a coordinate 0.5 is called int23");
    long zeros = 0, bad = 0;
    for (int t = 0; t < 100000; t++) {
        double q[5][3], o[3];
        for (int j = 0; j < 3; j++) o[j] = (double)tu_below(&r, 1u << 23) - 0x1p22;
        if (t & 1) {  /* 5 corners of a box with sides up to 2^21 */
            double side[3];
            for (int j = 0; j < 3; j++) side[j] = 1 + (double)tu_below(&r, 1u << 21);
            int used = 0;
            for (int i = 0; i < 5; i++) {
                int c;
                do c = (int)tu_below(&r, 8); while (used & (1 << c));
                used |= 1 << c;
                for (int j = 0; j < 3; j++) q[i][j] = o[j] + ((c >> j) & 1 ? side[j] : 0);
            }
        } else {  /* a paraboloid on a 9 x 9 grid, scaled by up to 4 in x and y */
            const double k = 1 + (double)tu_below(&r, 4);
            for (int i = 0; i < 5; i++) {
                const double x = (double)tu_below(&r, 9) - 4, y = (double)tu_below(&r, 9) - 4;
                q[i][0] = o[0] + k * x;
                q[i][1] = o[1] + k * y;
                q[i][2] = o[2] + k * k * (x * x + y * y);
            }
        }
        gtet_pred_counters k_cnt;
        if (!usable_tuple(q, &k_cnt)) continue;
        for (int swap = 0; swap < 2; swap++) {
            const double *v[5] = {q[swap], q[1 - swap], q[2], q[3], q[4]};
            const int f = pred_insphere_filter(v[0], v[1], v[2], v[3], v[4], ps.is_seps, NULL);
            const int ref = pred_insphere_sos(v[0], v[1], v[2], v[3], v[4], &k_cnt);
            const int got = f ? f : pred_insphere_sos_rest(v[0], v[1], v[2], v[3], v[4], &ps,
                                                           NULL, &k_cnt);
            bad += got != ref;
        }
        int s0, s1;
        pred_i128 mn[4];
        TEST_REQUIRE(pred_insphere_int_m(q[0], q[1], q[2], q[3], q[4], 1, &s1, mn) &&
                     pred_insphere_int_m(q[0], q[1], q[2], q[3], q[4], 0, &s0, NULL) && s0 == s1,
                     "the integer stage with and without its checks differ");
        if (s1 != 0) continue;
        zeros++;
        const pred_i128 want[5] = {mn[1], -mn[2], mn[3], -mn[0], ((mn[1] - mn[2]) + mn[3]) - mn[0]};
        for (int k = 0; k < 5; k++) {
            const double *w[4] = {q[0], q[1], q[2], q[3]};
            if (k < 4) w[k] = q[4];
            bad += pred_orient3d(w[0], w[1], w[2], w[3], &k_cnt) != (want[k] > 0) - (want[k] < 0);
        }
    }
    TEST_CHECK(zeros > 20000, "only %ld exactly co-spherical tuples", zeros);
    TEST_CHECK(bad == 0, "%ld disagreements between the integer path and the general rule", bad);
}

/* The lattice path ranks points by one exact key, (p-e)_x 2^22 + (p-e)_y 2^11 + (p-e)_z
 * (sos.c lex_top2_lattice), instead of coordinate-wise lexicographic compares.  That is right
 * only while every coordinate difference stays below 2^10 units, so test it where it is
 * tightest: point sets of exactly E = 659 units per axis (the largest the lattice path
 * accepts), at scales 2^-214 .. 2^194 and offsets on and off the origin; the 5 points are
 * corners of boxes inside that cube (any 5 corners of a box are co-spherical, so the insphere
 * is an exact zero and the ranking decides), with one side of 1 unit and another of 658 or 659
 * units (a tie in x broken by y and z terms of the largest size, and the reverse).  Every
 * decision must equal the general pred_insphere_sos. */
static void test_lattice_ranking_at_the_largest_extent_matches_the_general_rule(void)
{
    tu_rng r = {659};
    const int scales[] = {-214, -1, 0, 3, 194};
    long zeros = 0, bad = 0;
    for (size_t si = 0; si < sizeof scales / sizeof scales[0]; si++) {
        const double u = ldexp(1.0, scales[si]);
        for (int oi = 0; oi < 2; oi++) {
            const double off = oi ? -1000003.0 : 0.0;  /* units; odd, so s is the scale */
            double box[2][3];
            for (int j = 0; j < 3; j++) {
                box[0][j] = off * u;
                box[1][j] = (off + 659) * u;
            }
            pred_static ps;
            pred_static_init(&box[0][0], 3, 2, &ps);
            TEST_REQUIRE(ps.is_exact, "E = 659 at scale 2^%d is not called exact", scales[si]);
            for (int t = 0; t < 20000; t++) {
                double lo[3], side[3];
                const double pick[4] = {1, 658, 659, 0};
                for (int j = 0; j < 3; j++) {
                    side[j] = pick[tu_below(&r, 3)];
                    if (tu_below(&r, 4) == 0) side[j] = 1 + (double)tu_below(&r, 659);
                    lo[j] = (double)tu_below(&r, (uint64_t)(660 - side[j]));
                }
                int corner[5], used = 0;
                for (int i = 0; i < 5; i++) {
                    int c;
                    do c = (int)tu_below(&r, 8); while (used & (1 << c));
                    used |= 1 << c;
                    corner[i] = c;
                }
                double q[5][3];
                for (int i = 0; i < 5; i++)
                    for (int j = 0; j < 3; j++)
                        q[i][j] = (off + lo[j] + ((corner[i] >> j) & 1 ? side[j] : 0)) * u;
                gtet_pred_counters k_cnt;
                memset(&k_cnt, 0, sizeof k_cnt);
                if (pred_orient3d(q[0], q[1], q[2], q[3], &k_cnt) == 0) continue;
                double mn[PRED_IS_NMINORS];
                const int f = pred_insphere_filter(q[0], q[1], q[2], q[3], q[4], ps.is_seps, mn);
                const int ref = pred_insphere_sos(q[0], q[1], q[2], q[3], q[4], &k_cnt);
                const int got =
                    f ? f : pred_insphere_sos_rest(q[0], q[1], q[2], q[3], q[4], &ps, mn, &k_cnt);
                zeros += f == 0;
                bad += got != ref;
            }
        }
    }
    TEST_CHECK(zeros > 100000, "only %ld exactly co-spherical tuples", zeros);
    TEST_CHECK(bad == 0, "%ld disagreements between the lattice ranking and the general rule", bad);
}

/* The largest magnitude of any intermediate (every product, difference and sum) of
 * pred_insphere_filter's evaluation (filter.h, in its order) of an integer tuple, computed
 * exactly; every operation of the filter is exact iff it is at most 2^53 (integers up to 2^53
 * are doubles, the inputs are integers).  Coordinates below 2^23: every value < 2^127. */
static pred_i128 filter_peak_;
static pred_i128 pk_(pred_i128 v)
{
    const pred_i128 m = v < 0 ? -v : v;
    if (m > filter_peak_) filter_peak_ = m;
    return v;
}
#define PK_MUL(x, y) pk_((pred_i128)(x) * (y))
#define PK_SUB(x, y) pk_((x) - (y))
#define PK_ADD(x, y) pk_((x) + (y))
static pred_i128 insphere_filter_peak(double q[5][3])
{
    pred_i128 t[4][3];
    filter_peak_ = 0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) t[i][j] = pk_((pred_i128)q[i][j] - (pred_i128)q[4][j]);
    const pred_i128 *A = t[0], *B = t[1], *C = t[2], *D = t[3];
    const pred_i128 ab = PK_SUB(PK_MUL(A[0], B[1]), PK_MUL(B[0], A[1]));
    const pred_i128 bc = PK_SUB(PK_MUL(B[0], C[1]), PK_MUL(C[0], B[1]));
    const pred_i128 cd = PK_SUB(PK_MUL(C[0], D[1]), PK_MUL(D[0], C[1]));
    const pred_i128 da = PK_SUB(PK_MUL(D[0], A[1]), PK_MUL(A[0], D[1]));
    const pred_i128 ac = PK_SUB(PK_MUL(A[0], C[1]), PK_MUL(C[0], A[1]));
    const pred_i128 bd = PK_SUB(PK_MUL(B[0], D[1]), PK_MUL(D[0], B[1]));
    const pred_i128 abc = PK_ADD(PK_SUB(PK_MUL(A[2], bc), PK_MUL(B[2], ac)), PK_MUL(C[2], ab));
    const pred_i128 bcd = PK_ADD(PK_SUB(PK_MUL(B[2], cd), PK_MUL(C[2], bd)), PK_MUL(D[2], bc));
    const pred_i128 cda = PK_ADD(PK_ADD(PK_MUL(C[2], da), PK_MUL(D[2], ac)), PK_MUL(A[2], cd));
    const pred_i128 dab = PK_ADD(PK_ADD(PK_MUL(D[2], ab), PK_MUL(A[2], bd)), PK_MUL(B[2], da));
    pred_i128 w[4];
    for (int i = 0; i < 4; i++)
        w[i] = PK_ADD(PK_ADD(PK_MUL(t[i][0], t[i][0]), PK_MUL(t[i][1], t[i][1])),
                      PK_MUL(t[i][2], t[i][2]));
    PK_ADD(PK_SUB(PK_MUL(w[2], dab), PK_MUL(w[3], abc)),
           PK_SUB(PK_MUL(w[0], bcd), PK_MUL(w[1], cda)));
    return filter_peak_;
}

/* The exact filter record (NOTES.md E90; filter.h PRED_IS_INT_EXACT, sos.c
 * pred_insphere_sos_rest_log, proofs/filters.md section 12): on a set of integers below 2^23
 * an undecided filter whose record has ((((X*Y)*Z)*M)*M) <= 2^46 evaluated exactly, so the
 * kernel takes its det~'s sign and its minors as exact.  Paraboloid tuples (x, y, x^2 + y^2),
 * scaled by k in x and y and k^2 in z, anywhere in (-2^22, 2^22)^3: on a 9 x 9 grid (k <= 40),
 * and on two concentric lattice circles (k <= 16; always co-spherical), so that XYZM^2 ranges
 * from ~2^20 to ~2^70 across the bound: wherever the record claims exactness, every
 * intermediate of the evaluation must be at most 2^53 (computed exactly), det~'s sign must be
 * the integer stage's and, on a zero, the minors its exact minors; the kernel's answer must equal the general pred_insphere_sos.  Tuples just inside
 * and beyond the bound must both occur, so a larger bound is seen to fail. */
static void test_exact_filter_record_on_small_integers_matches_the_integer_stage(void)
{
    tu_rng r = {46};
    pred_static ps;
    TEST_REQUIRE(int23_static(&ps), "the set (-2^23, 2^23)^3 is not called int23");
    /* 12 lattice points on each of the circles x^2 + y^2 = 25, 50, 65 */
    static const int circle[3][12][2] = {
        {{5, 0}, {-5, 0}, {0, 5}, {0, -5}, {3, 4}, {-3, 4}, {3, -4}, {-3, -4}, {4, 3}, {-4, 3},
         {4, -3}, {-4, -3}},
        {{1, 7}, {-1, 7}, {1, -7}, {-1, -7}, {7, 1}, {-7, 1}, {7, -1}, {-7, -1}, {5, 5}, {-5, 5},
         {5, -5}, {-5, -5}},
        {{1, 8}, {-1, 8}, {1, -8}, {-1, -8}, {8, 1}, {-8, 1}, {8, -1}, {-8, -1}, {4, 7}, {-4, 7},
         {7, 4}, {-7, -4}}};
    long claims = 0, near = 0, beyond = 0, zeros = 0, bad = 0;
    for (int t = 0; t < 100000; t++) {
        double q[5][3], o[3];
        for (int j = 0; j < 3; j++) o[j] = (double)tu_below(&r, 1u << 22) - 0x1p21;
        const double k = 1 + (double)tu_below(&r, t & 1 ? 40 : 16);
        const int c1 = (int)tu_below(&r, 3), c2 = (c1 + 1 + (int)tu_below(&r, 2)) % 3;
        for (int i = 0; i < 5; i++) {
            double x = (double)tu_below(&r, 9) - 4, y = (double)tu_below(&r, 9) - 4;
            if (!(t & 1)) {  /* two concentric circles of the paraboloid: co-spherical */
                const int *pt = circle[i < 2 ? c1 : c2][tu_below(&r, 12)];
                x = pt[0];
                y = pt[1];
            }
            q[i][0] = o[0] + k * x;
            q[i][1] = o[1] + k * y;
            q[i][2] = o[2] + k * k * (x * x + y * y);
        }
        gtet_pred_counters k_cnt;
        if (!usable_tuple(q, &k_cnt)) continue;
        double mn[PRED_IS_NMINORS];
        const int f = pred_insphere_filter(q[0], q[1], q[2], q[3], q[4], ps.is_seps, mn);
        const int ref = pred_insphere_sos(q[0], q[1], q[2], q[3], q[4], &k_cnt);
        const int got = f ? f : pred_insphere_sos_rest(q[0], q[1], q[2], q[3], q[4], &ps, mn,
                                                       &k_cnt);
        bad += got != ref;
        if (f != 0) continue;
        if (!(mn[5] <= PRED_IS_INT_EXACT)) {
            beyond++;
            continue;
        }
        claims++;
        near += mn[5] > PRED_IS_INT_EXACT / 64;
        bad += insphere_filter_peak(q) > ((pred_i128)1 << 53);
        int s;
        pred_i128 im[4];
        TEST_REQUIRE(pred_insphere_int_m(q[0], q[1], q[2], q[3], q[4], 1, &s, im),
                     "the integer stage refused an int23 tuple");
        bad += s != (mn[4] > 0) - (mn[4] < 0);
        if (s != 0) continue;
        zeros++;
        for (int m = 0; m < 4; m++)
            bad += !(fabs(mn[m]) < 0x1p100) || (pred_i128)mn[m] != im[m];
    }
    TEST_CHECK(claims > 10000 && zeros > 10000, "only %ld exact records, %ld zeros", claims,
               zeros);
    TEST_CHECK(near > 1000 && beyond > 1000, "%ld records within 2^6 of the bound, %ld beyond",
               near, beyond);
    printf("exact records %ld (zeros %ld, within 2^6 of the bound %ld), beyond %ld\n", claims,
           zeros, near, beyond);
    TEST_CHECK(bad == 0, "%ld disagreements with the integer stage or the general rule", bad);
}

/* The ranking on small integers (sos.c lex_top2_int23, NOTES.md E91): 5 corners of boxes whose
 * sides reach the ends of int23's range (coordinates +-(2^23 - 1)) on some axes and are 1 or 2
 * units on the others (every tuple co-spherical, so the perturbation ranks them), in every
 * choice of e and both orientations: the kernel's answer (pred_insphere_sos_rest on an int23
 * set) must equal the general pred_insphere_sos, whose ranks compare coordinates.  A weight
 * below 2^24 for x in the ranking key (or a reversed z) fails it. */
static void test_int23_ranking_at_the_largest_coordinates_matches_the_general_rule(void)
{
    const double L = 0x1p23 - 1;
    double box[2][3] = {{-L, -L, -L}, {L, L, L}};
    pred_static ps;
    pred_static_init(&box[0][0], 3, 2, &ps);
    TEST_REQUIRE(ps.int23 && !ps.is_exact, "the set [-(2^23-1), 2^23-1]^3 is not called int23");
    long zeros = 0, bad = 0;
    for (int wide = 1; wide < 7; wide++)      /* the axes whose side spans the whole range */
        for (int small = 1; small <= 2; small++)
            for (int pick = 0; pick < 256; pick++) {
                if (__builtin_popcount((unsigned)pick) != 5) continue;
                double q[5][3];
                for (int c = 0, i = 0; c < 8; c++) {
                    if (!(pick >> c & 1)) continue;
                    for (int j = 0; j < 3; j++) {
                        const int hi = c >> j & 1;
                        q[i][j] = wide >> j & 1 ? (hi ? L : -L) : (hi ? 5 + small : 5);
                    }
                    i++;
                }
                for (int e = 0; e < 5; e++)
                    for (int swap = 0; swap < 2; swap++) {
                        const double *v[5];
                        for (int i = 0, o = 0; i < 5; i++)
                            if (i != e) v[o++] = q[i];
                        v[4] = q[e];
                        if (swap) {
                            const double *t = v[0];
                            v[0] = v[1];
                            v[1] = t;
                        }
                        gtet_pred_counters k_cnt;
                        memset(&k_cnt, 0, sizeof k_cnt);
                        if (pred_orient3d(v[0], v[1], v[2], v[3], &k_cnt) == 0) continue;
                        double mn[PRED_IS_NMINORS];
                        const int f =
                            pred_insphere_filter(v[0], v[1], v[2], v[3], v[4], ps.is_seps, mn);
                        const int ref = pred_insphere_sos(v[0], v[1], v[2], v[3], v[4], &k_cnt);
                        const int got = f ? f : pred_insphere_sos_rest(v[0], v[1], v[2], v[3],
                                                                       v[4], &ps, mn, &k_cnt);
                        zeros += f == 0;
                        bad += got != ref;
                    }
            }
    TEST_CHECK(zeros > 1000, "only %ld co-spherical tuples", zeros);
    TEST_CHECK(bad == 0, "%ld disagreements between the int23 ranking and the general rule", bad);
}

int main(void)
{
    TU_RUN(test_insphere_sos_hand_checked_cube_cases);
    TU_RUN(test_insphere_sos_on_all_5_subsets_of_cube_corners);
    TU_RUN(test_insphere_sos_on_cospherical_lattice_points_and_small_grid);
    TU_RUN(test_ghost_conflict_is_never_zero_and_consistent_with_coplanar_circle);
    TU_RUN(test_ghost_conflict_at_extreme_scales_matches_oracle);
    TU_RUN(test_lattice_perturbation_from_minors_matches_the_general_rule);
    TU_RUN(test_lattice_ranking_at_the_largest_extent_matches_the_general_rule);
    TU_RUN(test_integer_perturbation_from_minors_matches_the_general_rule);
    TU_RUN(test_exact_filter_record_on_small_integers_matches_the_integer_stage);
    TU_RUN(test_int23_ranking_at_the_largest_coordinates_matches_the_general_rule);
    printf("sos decisions %llu (depth %llu %llu %llu %llu)\n", (unsigned long long)cnt.sos_calls,
           (unsigned long long)cnt.sos_depth[0], (unsigned long long)cnt.sos_depth[1],
           (unsigned long long)cnt.sos_depth[2], (unsigned long long)cnt.sos_depth[3]);
    return tu_finish();
}
