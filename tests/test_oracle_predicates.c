/* test_oracle_predicates.c -- the GMP oracle (src/oracle) on hand-checked cases and against a
 * second, deliberately naive exact evaluation in mpq (mpq_set_d is exact) written here.
 *
 * Hand-checked: the unit simplex and its mirror images, the cube corners (co-spherical: exact
 * insphere 0) and their centre, perturbed decisions traced by hand through CGAL's rule, the hull
 * rule in and out of the facet plane.  Properties: sign flips under odd permutations, the
 * perturbed sign is never 0 and equals the exact sign when that is nonzero, the two sides of a
 * shared facet agree, extreme scales (2^-1074, 2^1000, mixed) are exact.
 */
#include <gmp.h>
#include <math.h>
#include <string.h>

#include "oracle/oracle.h"
#include "testutil.h"

/* ---- naive reference: mpq determinants, no scaling tricks ---- */

static void q_det3(mpq_t r, mpq_t m[9])
{
    mpq_t t, u;
    mpq_inits(t, u, NULL);
    mpq_set_ui(r, 0, 1);
    for (int c = 0; c < 3; c++) {
        int c1 = (c + 1) % 3, c2 = (c + 2) % 3;  /* cyclic: signs are all + */
        mpq_mul(t, m[3 + c1], m[6 + c2]);
        mpq_mul(u, m[3 + c2], m[6 + c1]);
        mpq_sub(t, t, u);
        mpq_mul(t, t, m[c]);
        mpq_add(r, r, t);
    }
    mpq_clears(t, u, NULL);
}

static int ref_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    const double *p[3] = {b, c, d};
    mpq_t m[9], r, t;
    mpq_inits(r, t, NULL);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            mpq_init(m[3 * i + j]);
            mpq_set_d(m[3 * i + j], p[i][j]);
            mpq_set_d(t, a[j]);
            mpq_sub(m[3 * i + j], m[3 * i + j], t);
        }
    q_det3(r, m);
    int s = mpq_sgn(r);
    for (int i = 0; i < 9; i++) mpq_clear(m[i]);
    mpq_clears(r, t, NULL);
    return s;
}

/* insphere as orient3d of the lifted points times -orient: the power of e with respect to the
 * sphere, computed as the sign of det[x-e, |x-e|^2] expanded along the lifted column. */
static int ref_insphere(const double *a, const double *b, const double *c, const double *d,
                        const double *e)
{
    const double *p[4] = {a, b, c, d};
    mpq_t x[4][4], r, t, minor;
    mpq_inits(r, t, minor, NULL);
    for (int i = 0; i < 4; i++) {
        mpq_init(x[i][3]);
        for (int j = 0; j < 3; j++) {
            mpq_init(x[i][j]);
            mpq_set_d(x[i][j], p[i][j]);
            mpq_set_d(t, e[j]);
            mpq_sub(x[i][j], x[i][j], t);
            mpq_mul(t, x[i][j], x[i][j]);
            mpq_add(x[i][3], x[i][3], t);
        }
    }
    for (int i = 0; i < 4; i++) {
        mpq_t m[9];
        int k = 0;
        for (int row = 0; row < 4; row++) {
            if (row == i) continue;
            for (int j = 0; j < 3; j++) {
                mpq_init(m[k]);
                mpq_set(m[k], x[row][j]);
                k++;
            }
        }
        q_det3(minor, m);
        for (k = 0; k < 9; k++) mpq_clear(m[k]);
        mpq_mul(t, minor, x[i][3]);
        if ((i + 3) % 2 == 0) mpq_add(r, r, t);
        else mpq_sub(r, r, t);
    }
    int s = -mpq_sgn(r);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) mpq_clear(x[i][j]);
    mpq_clears(r, t, minor, NULL);
    return s;
}

static const double O[3] = {0, 0, 0}, EX[3] = {1, 0, 0}, EY[3] = {0, 1, 0}, EZ[3] = {0, 0, 1};

static void test_orient3d_unit_simplex_is_positive_and_flips_with_odd_permutations(void)
{
    TEST_CHECK(orc_orient3d(O, EX, EY, EZ) == 1, "(0,ex,ey,ez) is not positive");
    TEST_CHECK(orc_orient3d(EX, O, EY, EZ) == -1, "swap a,b does not flip");
    TEST_CHECK(orc_orient3d(O, EX, EZ, EY) == -1, "swap c,d does not flip");
    TEST_CHECK(orc_orient3d(EY, EZ, O, EX) == 1, "even permutation changes the sign");
    const double half[3] = {0.5, 0.5, 0};
    TEST_CHECK(orc_orient3d(O, EX, EY, half) == 0, "coplanar is not 0");
    const double below[3] = {0.3, 0.3, -1e-300};
    TEST_CHECK(orc_orient3d(O, EX, EY, below) == -1, "a point 1e-300 below is not negative");
}

static void test_orient3d_is_exact_at_extreme_and_mixed_scales(void)
{
    const double big = 0x1p1000, tiny = 0x1p-1074;
    const double a[3] = {0, 0, 0}, bx[3] = {big, 0, 0}, by[3] = {0, big, 0}, bz[3] = {0, 0, big};
    TEST_CHECK(orc_orient3d(a, bx, by, bz) == 1, "2^1000 simplex");
    const double tx[3] = {tiny, 0, 0}, ty[3] = {0, tiny, 0}, tz[3] = {0, 0, tiny};
    TEST_CHECK(orc_orient3d(a, tx, ty, tz) == 1, "denormal simplex");
    TEST_CHECK(orc_orient3d(a, bx, ty, tz) == 1, "mixed 2^1000 / 2^-1074 simplex");
    /* A point on the plane x + y + z = 2^1000 moved by one denormal. */
    const double on[3] = {0x1p999, 0x1p998, 0x1p998};
    const double off[3] = {0x1p999, 0x1p998, 0x1p998 + 0x1p946};  /* one ulp of 2^998 */
    TEST_CHECK(orc_orient3d(bx, by, bz, on) == 0, "a point on the big plane is not coplanar");
    TEST_CHECK(orc_orient3d(bx, by, bz, off) == -orc_orient3d(bx, by, bz, a),
               "one ulp beyond the big plane is not on the far side from the origin");
}

static void test_insphere_unit_simplex_inside_outside_and_sign_flip(void)
{
    const double in[3] = {0.25, 0.25, 0.25}, out[3] = {2, 2, 2};
    TEST_CHECK(orc_insphere(O, EX, EY, EZ, in) == 1, "centre-ish point not inside");
    TEST_CHECK(orc_insphere(O, EX, EY, EZ, out) == -1, "far point not outside");
    TEST_CHECK(orc_insphere(EX, O, EY, EZ, in) == -1, "odd permutation does not flip");
    TEST_CHECK(orc_insphere(O, EX, EY, EZ, O) == 0, "a vertex is not on the sphere");
}

/* The 8 corners of the unit cube. */
static void cube(double c[8][3])
{
    for (int i = 0; i < 8; i++) {
        c[i][0] = (double)(i & 1);
        c[i][1] = (double)((i >> 1) & 1);
        c[i][2] = (double)((i >> 2) & 1);
    }
}

/* Exercises proofs/perturbation.md P1. */
static void test_cube_corners_are_cospherical_and_centre_inside(void)
{
    double c[8][3];
    cube(c);
    const double mid[3] = {0.5, 0.5, 0.5};
    int tets = 0;
    for (int a = 0; a < 8; a++)
        for (int b = 0; b < 8; b++)
            for (int d3 = 0; d3 < 8; d3++)
                for (int d = 0; d < 8; d++) {
                    int o = orc_orient3d(c[a], c[b], c[d3], c[d]);
                    if (o == 0) continue;
                    tets++;
                    TEST_CHECK(orc_insphere(c[a], c[b], c[d3], c[d], mid) == o,
                               "centre not inside the circumsphere of corners %d %d %d %d",
                               a, b, d3, d);
                    for (int e = 0; e < 8; e++)
                        TEST_CHECK(orc_insphere(c[a], c[b], c[d3], c[d], c[e]) == 0,
                                   "corner %d not on the sphere of %d %d %d %d", e, a, b, d3, d);
                }
    TEST_CHECK(tets == 58 * 24, "expected 58 non-degenerate corner 4-sets, got %d/24", tets);
}

/* Exercises proofs/perturbation.md P1. */
static void test_insphere_sos_hand_traced_cube_cases(void)
{
    /* Traced by hand through CGAL's side_of_oriented_sphere with perturb=true. */
    const double c000[3] = {0, 0, 0}, c100[3] = {1, 0, 0}, c010[3] = {0, 1, 0},
                 c001[3] = {0, 0, 1}, c110[3] = {1, 1, 0}, c111[3] = {1, 1, 1};
    /* (0,ex,ey,ez), e = (1,1,1): e ranks highest -> -1 */
    TEST_CHECK(orc_insphere_sos(c000, c100, c010, c001, c111) == -1, "case e highest");
    /* p3 = (1,1,1) highest: orient(p0,p1,p2,e) with e = (0,0,1): +1 */
    TEST_CHECK(orc_insphere_sos(c000, c100, c010, c111, c001) == 1, "case p3 highest");
    /* p3 highest but e = (1,1,0) coplanar with p0,p1,p2; next is e -> -1 */
    TEST_CHECK(orc_insphere_sos(c000, c100, c010, c111, c110) == -1, "case p3 then e");
    /* (0, ex, (1,1,0), (1,1,1)), e = (0,1,0): p3 gives 0, then p2 = (1,1,0):
     * orient(0, ex, e, (1,1,1)) = +1 */
    TEST_CHECK(orc_insphere_sos(c000, c100, c110, c111, c010) == 1, "case p3 then p2");
    /* the mirror images flip */
    TEST_CHECK(orc_insphere_sos(c100, c000, c010, c111, c001) == -1, "mirror of case p3");
    TEST_CHECK(orc_insphere_sos(c100, c000, c110, c111, c010) == -1, "mirror of p3 then p2");
}

static const int PERM_ODD[6][4] = {{1, 0, 2, 3}, {0, 2, 1, 3}, {0, 1, 3, 2},
                                   {3, 1, 2, 0}, {2, 1, 0, 3}, {1, 2, 3, 0}};

/* Exercises proofs/perturbation.md P2, P3. */
static void test_insphere_sos_on_cube_is_never_zero_and_antisymmetric(void)
{
    double c[8][3];
    cube(c);
    for (int a = 0; a < 8; a++)
        for (int b = 0; b < 8; b++)
            for (int g = 0; g < 8; g++)
                for (int d = 0; d < 8; d++) {
                    if (orc_orient3d(c[a], c[b], c[g], c[d]) == 0) continue;
                    const double *t[4] = {c[a], c[b], c[g], c[d]};
                    for (int e = 0; e < 8; e++) {
                        if (e == a || e == b || e == g || e == d) continue;
                        int s = orc_insphere_sos(t[0], t[1], t[2], t[3], c[e]);
                        TEST_CHECK(s == 1 || s == -1, "sos 0 on corners %d%d%d%d,%d", a, b, g, d, e);
                        for (int k = 0; k < 6; k++) {
                            const int *p = PERM_ODD[k];
                            int s2 = orc_insphere_sos(t[p[0]], t[p[1]], t[p[2]], t[p[3]], c[e]);
                            TEST_CHECK(s2 == -s, "odd permutation %d does not flip", k);
                        }
                    }
                }
}

/* Two tets sharing facet (a,b,c) with apexes d (t1 = (a,b,c,d)) and e on the other side: the
 * perturbed test of e against t1 equals that of d against t2 = (a,c,b,e) (both positive). */
/* Exercises proofs/perturbation.md P3, P6. */
static void test_insphere_sos_agrees_from_both_sides_of_a_facet_on_a_grid(void)
{
    tu_rng r = {7};
    int tested = 0;
    for (int it = 0; it < 4000; it++) {
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = (double)tu_below(&r, 3);
        int distinct = 1;
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < i; k++)
                if (orc_lex_compare(p[i], p[k]) == 0) distinct = 0;
        if (!distinct) continue;
        int o1 = orc_orient3d(p[0], p[1], p[2], p[3]);
        int o2 = orc_orient3d(p[0], p[2], p[1], p[4]);
        if (o1 <= 0 || o2 <= 0) continue;
        tested++;
        int s1 = orc_insphere_sos(p[0], p[1], p[2], p[3], p[4]);
        int s2 = orc_insphere_sos(p[0], p[2], p[1], p[4], p[3]);
        TEST_CHECK(s1 == s2 && s1 != 0, "facet sides disagree: %d vs %d (iteration %d)", s1, s2, it);
        int ex = orc_insphere(p[0], p[1], p[2], p[3], p[4]);
        if (ex != 0) TEST_CHECK(s1 == ex, "sos differs from a nonzero exact sign");
    }
    TEST_CHECK(tested > 100, "only %d grid facet pairs tested", tested);
}

static double rnd_coord(tu_rng *r, int family)
{
    double u = tu_uniform(r) - 0.5;
    switch (family) {
    case 0: return u;                                          /* plain */
    case 1: return (double)((int)tu_below(r, 5) - 2);          /* small integers */
    case 2: return ldexp(u, 1000);                             /* huge */
    case 3: return ldexp(u, -1060);                            /* (partly) denormal */
    case 4: return tu_below(r, 2) ? ldexp(u, 900) : ldexp(u, -1000);  /* mixed */
    case 5: return 1.0 + ldexp((double)tu_below(r, 4), -52);  /* 1-ulp neighbours of 1 */
    case 6: return (double)(int64_t)(tu_next(r) >> 33) - 0x1p30;  /* 31-bit integers */
    default: return 0x1p22 - (double)tu_below(r, 3);          /* at the small-path bound */
    }
}

static void test_predicates_equal_naive_mpq_reference_on_adversarial_families(void)
{
    tu_rng r = {12345};
    int zeros = 0;
    for (int it = 0; it < 1800; it++) {
        int fam = it % 8;
        double p[5][3];
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 3; j++) p[i][j] = rnd_coord(&r, fam);
        int o = orc_orient3d(p[0], p[1], p[2], p[3]);
        TEST_CHECK(o == ref_orient3d(p[0], p[1], p[2], p[3]), "orient3d differs (family %d)", fam);
        int s = orc_insphere(p[0], p[1], p[2], p[3], p[4]);
        TEST_CHECK(s == ref_insphere(p[0], p[1], p[2], p[3], p[4]), "insphere differs (family %d)", fam);
        zeros += (o == 0) + (s == 0);
        for (int drop = 0; drop < 3; drop++) {
            /* orient2d in a projection equals orient3d with a unit step along the dropped axis:
             * det[b-a; c-a; e_k] = +-orient2d, sign fixed by the axis order */
            double d[3] = {p[0][0], p[0][1], p[0][2]};
            d[drop] += 1.0;
            if (fam >= 2 && fam <= 4) continue;  /* +1 would be absorbed at those scales */
            int o3 = orc_orient3d(p[0], p[1], p[2], d);
            int sgn = drop == 1 ? -1 : 1;        /* (x,z) is an odd order of (z,x) */
            TEST_CHECK(orc_orient2d_proj(p[0], p[1], p[2], drop) == sgn * o3,
                       "orient2d projection %d differs from orient3d with e_%d", drop, drop);
        }
    }
    TEST_CHECK(zeros > 20, "the families produced only %d exact zeros", zeros);
}

/* Exercises proofs/perturbation.md P5. */
static void test_ghost_conflict_hand_cases(void)
{
    /* Facet (0, ey, ex) has orient3d < 0 for points above z = 0: the hull side. */
    const double a[3] = {0, 0, 0}, b[3] = {0, 1, 0}, c[3] = {1, 0, 0};
    TEST_CHECK(orc_orient3d(a, b, c, EZ) == -1, "setup: ez not on the hull side");
    const double below[3] = {0.3, 0.3, -1}, above[3] = {5, 5, 1};
    TEST_CHECK(orc_ghost_conflict(a, b, c, below) == 1, "point beyond the facet not in conflict");
    TEST_CHECK(orc_ghost_conflict(a, b, c, above) == -1, "hull-side point in conflict");
    const double inside[3] = {0.2, 0.2, 0}, outside[3] = {5, 5, 0};
    TEST_CHECK(orc_ghost_conflict(a, b, c, inside) == 1, "coplanar point inside the circle");
    TEST_CHECK(orc_ghost_conflict(a, b, c, outside) == -1, "coplanar point outside the circle");
    /* cocircular (1,1,0): ranks (0,0,0) < (0,1,0) < (1,0,0) < (1,1,0): e highest -> -1 */
    const double c110[3] = {1, 1, 0};
    TEST_CHECK(orc_ghost_conflict(a, b, c, c110) == -1, "cocircular, e highest");
    /* (0, ey, (1,1,0)) with e = (1,0,0): c = (1,1,0) highest; coplanar_orientation(a,b,e) = -1,
     * local = coplanar_orientation(a,b,c) = -1: +1 */
    TEST_CHECK(orc_ghost_conflict(a, b, c110, c) == 1, "cocircular, p2 highest");
    /* the vertical plane x = 0: the xy projection is collinear, yz decides */
    const double v0[3] = {0, 0, 0}, v1[3] = {0, 1, 0}, v2[3] = {0, 0, 1}, vin[3] = {0, 0.3, 0.3};
    TEST_CHECK(orc_coplanar_orientation(v0, v1, v2) == 1, "yz orientation of a vertical facet");
    TEST_CHECK(orc_coplanar_circle_sos(v0, v1, v2, vin) == 1, "inside a vertical circle");
}

/* Exercises proofs/perturbation.md P5. */
static void test_coplanar_circle_sos_is_symmetric_in_the_facet_and_never_zero(void)
{
    /* The four corners of squares in the three coordinate planes: all cocircular. */
    double sq[3][4][3];
    memset(sq, 0, sizeof sq);
    for (int pl = 0; pl < 3; pl++)
        for (int i = 0; i < 4; i++) {
            int u = (pl + 1) % 3, v = (pl + 2) % 3;
            sq[pl][i][u] = (double)(i & 1);
            sq[pl][i][v] = (double)(i >> 1);
            sq[pl][i][pl] = 0.75;
        }
    static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
    for (int pl = 0; pl < 3; pl++)
        for (int e = 0; e < 4; e++) {
            int f[3], k = 0;
            for (int i = 0; i < 4; i++)
                if (i != e) f[k++] = i;
            int s0 = orc_coplanar_circle_sos(sq[pl][f[0]], sq[pl][f[1]], sq[pl][f[2]], sq[pl][e]);
            TEST_CHECK(s0 == 1 || s0 == -1, "perturbed circle test is %d", s0);
            for (int p = 1; p < 6; p++) {
                int s = orc_coplanar_circle_sos(sq[pl][f[perm[p][0]]], sq[pl][f[perm[p][1]]],
                                                sq[pl][f[perm[p][2]]], sq[pl][e]);
                TEST_CHECK(s == s0, "plane %d, e %d: permutation %d of the facet changes %d to %d",
                           pl, e, p, s0, s);
            }
        }
}

int main(void)
{
    TU_RUN(test_orient3d_unit_simplex_is_positive_and_flips_with_odd_permutations);
    TU_RUN(test_orient3d_is_exact_at_extreme_and_mixed_scales);
    TU_RUN(test_insphere_unit_simplex_inside_outside_and_sign_flip);
    TU_RUN(test_cube_corners_are_cospherical_and_centre_inside);
    TU_RUN(test_insphere_sos_hand_traced_cube_cases);
    TU_RUN(test_insphere_sos_on_cube_is_never_zero_and_antisymmetric);
    TU_RUN(test_insphere_sos_agrees_from_both_sides_of_a_facet_on_a_grid);
    TU_RUN(test_predicates_equal_naive_mpq_reference_on_adversarial_families);
    TU_RUN(test_ghost_conflict_hand_cases);
    TU_RUN(test_coplanar_circle_sos_is_symmetric_in_the_facet_and_never_zero);
    return tu_finish();
}
