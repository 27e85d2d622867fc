/* test_check_diff.c -- the closed Delaunay mode of the checker and gtet_diff on small meshes
 * whose answers are known by hand:
 *   - the cube's 8 co-spherical corners: the canonical 6-tet split and the 5-tet split (four
 *     corner tets around a central one) are both Delaunay in the closed sense; the diff is one
 *     tie group of 8 points on the hull;
 *   - two cubes side by side (a 3x2x2 grid): two groups;
 *   - a flat bipyramid (a triangle with an apex just above and just below): the 3 tets around
 *     the apexes' edge are Delaunay; the 2 tets on the triangle are a valid triangulation that
 *     is not, and fail both modes; the diff names that side;
 *   - a renumbered, reoriented copy is identical; a moved vertex is a different point set.
 */
#include <stdio.h>
#include <string.h>

#include "test_check_meshes.h"
#include "testutil.h"

static void cube(double v[24])
{
    for (int i = 0; i < 8; i++) {
        v[3 * i] = i & 1;
        v[3 * i + 1] = (i >> 1) & 1;
        v[3 * i + 2] = (i >> 2) & 1;
    }
}

/* corners 0, 3, 5, 6 cut off from the central tet (1, 2, 4, 7) */
static const uint32_t five_split[20] = {0, 1, 2, 4, 3, 1, 2, 7, 5, 1, 4, 7, 6, 2, 4, 7, 1, 2, 4, 7};

static gtet_status check(const tmesh *m, unsigned flags, gtet_check_report *r)
{
    return gtet_check_arrays(m->v, m->nv, m->t, m->nt, NULL, m->v, m->nv, flags, r);
}

static gtet_status diff(const tmesh *a, const tmesh *b, gtet_diff_report *r)
{
    return gtet_diff(a->v, a->nv, a->t, a->nt, b->v, b->nv, b->t, b->nt, a->v, a->nv, r);
}

static void test_both_cube_splits_are_delaunay_and_differ_by_one_group(void)
{
    double v[24];
    cube(v);
    tmesh six = tm_brute_delaunay(v, 8), five = tm_make(v, 8, five_split, 5);
    gtet_check_report r;
    TEST_CHECK(check(&six, GTET_CHECK_FULL, &r) == GTET_OK, "canonical split: %s", r.message);
    TEST_CHECK(check(&five, GTET_CHECK_DELAUNAY | GTET_CHECK_FULL, &r) == GTET_OK && r.mode == GTET_CHECK_DELAUNAY,
               "5-tet split in closed mode: %s", r.message);
    /* every interior facet of the 5-tet split is co-spherical; the hull's 6 squares are split */
    TEST_CHECK(r.cospherical_facets == 4 && r.coplanar_hull_edges == 6, "ties: %llu facets, %llu hull edges",
               (unsigned long long)r.cospherical_facets, (unsigned long long)r.coplanar_hull_edges);
    TEST_CHECK(check(&five, 0, &r) == GTET_ERR_CHECK_FAILED && r.violation.tie && r.violation.group_size == 8,
               "5-tet split in canonical mode: %s", r.message);
    gtet_diff_report d;
    TEST_REQUIRE(diff(&six, &five, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_TIES && d.num_groups == 1 && d.only_a > 0 &&
                   d.common + d.only_a == 6 && d.common + d.only_b == 5, "diff: %s (kind %d, groups %llu)", d.message, (int)d.kind,
               (unsigned long long)d.num_groups);
    if (d.num_groups == 1) {
        const gtet_diff_group *g = &d.groups[0];
        TEST_CHECK(g->size == 8 && g->tets_a == 6 && g->tets_b == 5 && g->on_hull &&
                       g->point[0] == 0 && g->point[1] == 0 && g->point[2] == 0 &&
                       g->center[0] == 0.5 && g->center[1] == 0.5 && g->center[2] == 0.5,
                   "group: size %llu, tets %llu/%llu, point (%g %g %g), centre (%g %g %g)",
                   (unsigned long long)g->size, (unsigned long long)g->tets_a,
                   (unsigned long long)g->tets_b, g->point[0], g->point[1], g->point[2],
                   g->center[0], g->center[1], g->center[2]);
    }
    gtet_diff_report_free(&d);
    tm_free(&six);
    tm_free(&five);
}

static void test_two_cubes_give_two_groups(void)
{
    double v[36];
    for (int i = 0; i < 12; i++) {
        v[3 * i] = i % 3;
        v[3 * i + 1] = (i / 3) % 2;
        v[3 * i + 2] = i / 6;
    }
    tmesh a = tm_brute_delaunay(v, 12);
    /* B: both cubes in 5 tets, the right one mirrored so that the shared square (x = 1) gets
     * the same diagonal from both sides */
    uint32_t t[40];
    static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                     {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    for (int c = 0; c < 2; c++)
        for (int k = 0; k < 20; k++) {
            const int *p = corner[five_split[k]];
            int x = c ? 2 - p[0] : p[0];
            t[20 * c + k] = (uint32_t)(x + 3 * p[1] + 6 * p[2]);
        }
    tmesh b = tm_make(v, 12, t, 10);
    gtet_check_report r;
    TEST_CHECK(check(&b, GTET_CHECK_DELAUNAY | GTET_CHECK_FULL, &r) == GTET_OK, "B: %s", r.message);
    gtet_diff_report d;
    TEST_REQUIRE(diff(&a, &b, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_TIES && d.num_groups == 2, "diff: %s", d.message);
    for (uint64_t i = 0; i < d.num_groups; i++)
        TEST_CHECK(d.groups[i].size == 8 && d.groups[i].tets_b == 5 && d.groups[i].point[0] == (double)i,
                   "group %llu: size %llu, B tets %llu, point x %g", (unsigned long long)i,
                   (unsigned long long)d.groups[i].size, (unsigned long long)d.groups[i].tets_b,
                   d.groups[i].point[0]);
    gtet_diff_report_free(&d);
    tm_free(&a);
    tm_free(&b);
}

static void test_flat_bipyramid_in_two_tets_fails_both_modes(void)
{
    /* triangle 0 1 2 in z = 0, apexes 3 (above) and 4 (below), close to the plane */
    const double v[15] = {0, 0, 0, 4, 0, 0, 0, 4, 0, 1, 1, 0.25, 1, 1, -0.25};
    const uint32_t two[8] = {0, 1, 2, 3, 0, 1, 2, 4};
    const uint32_t three[12] = {0, 1, 3, 4, 1, 2, 3, 4, 2, 0, 3, 4};
    tmesh m2 = tm_make(v, 5, two, 2), m3 = tm_make(v, 5, three, 3), truth = tm_brute_delaunay(v, 5);
    TEST_CHECK(tm_same_tets(&m3, &truth), "the 3-tet bipyramid is not the Delaunay one");
    gtet_check_report r;
    for (int mode = 0; mode < 2; mode++) {
        unsigned fl = mode ? (unsigned)GTET_CHECK_DELAUNAY : 0u;
        TEST_CHECK(check(&m3, fl | GTET_CHECK_FULL, &r) == GTET_OK, "3 tets, mode %d: %s", mode, r.message);
        TEST_CHECK(check(&m2, fl, &r) == GTET_ERR_CHECK_FAILED && strstr(r.message, "not locally Delaunay") &&
                       !r.violation.tie && !strcmp(r.violation.stage, "delaunay") &&
                       r.violation.nvertices == 5 && r.violation.tet[1] != GTET_CHECK_NONE,
                   "2 tets, mode %d: %s", mode, r.message);
    }
    gtet_diff_report d;
    TEST_REQUIRE(diff(&m2, &m3, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_A_NOT_DELAUNAY && !d.check_a.ok && d.check_b.ok &&
                   strstr(d.message, "A is not Delaunay"), "diff 2 vs 3: %s", d.message);
    gtet_diff_report_free(&d);
    TEST_REQUIRE(diff(&m3, &m2, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_B_NOT_DELAUNAY, "diff 3 vs 2: %s", d.message);
    gtet_diff_report_free(&d);
    tm_free(&m2);
    tm_free(&m3);
    tm_free(&truth);
}

static void test_renumbered_reoriented_copy_is_identical_and_moved_point_is_not(void)
{
    double *p = tm_random_points(7, 30);
    tmesh a = tm_brute_delaunay(p, 30), b = tm_make(p, 30, a.t, a.nt);
    /* reverse the vertex numbering and swap two vertices of every other tet */
    for (size_t i = 0; i < 30; i++) memcpy(b.v + 3 * (29 - i), p + 3 * i, 3 * sizeof *p);
    for (size_t i = 0; i < 4 * b.nt; i++) b.t[i] = 29 - b.t[i];
    for (size_t t = 0; t < b.nt; t += 2) {
        uint32_t x = b.t[4 * t];
        b.t[4 * t] = b.t[4 * t + 2];
        b.t[4 * t + 2] = x;
    }
    gtet_diff_report d;
    TEST_REQUIRE(diff(&a, &b, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_IDENTICAL && d.common == a.nt, "renumbered copy: %s", d.message);
    gtet_diff_report_free(&d);
    b.v[3 * 5] += 1e-9;
    TEST_REQUIRE(diff(&a, &b, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_POINTS && d.points_only_a == 1 && d.points_only_b == 1,
               "moved point: %s", d.message);
    /* NOTES.md E181: a point moved by a tiny relative amount is named with the other mesh's
     * nearest point, as if a writer had rounded it; one moved far is not */
    TEST_CHECK(strstr(d.message, "nearest point (") &&
                   strstr(d.message, "were the coordinates rounded when a mesh was written?"),
               "moved by 1e-9: no rounding note: %s", d.message);
    gtet_diff_report_free(&d);
    b.v[3 * 5] += 0.5;
    TEST_REQUIRE(diff(&a, &b, &d) == GTET_OK, "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_POINTS && !strstr(d.message, "rounded"),
               "moved by 0.5: %s", d.message);
    gtet_diff_report_free(&d);
    TEST_CHECK(gtet_diff(NULL, 3, a.t, a.nt, b.v, b.nv, b.t, b.nt, NULL, 0, &d) == GTET_ERR_ARGUMENT,
               "NULL vertices accepted");
    tm_free(&a);
    tm_free(&b);
    free(p);
}

/* A tool that keeps duplicate input points writes them as vertices in no tet: accepted as
 * copies (and counted); a vertex in no tet that is not a copy is a missing point. */
static void test_unused_copies_are_accepted_and_unused_points_are_not(void)
{
    double *p = tm_random_points(9, 20);
    tmesh a = tm_brute_delaunay(p, 20);
    double v[3 * 22];
    memcpy(v, p, 60 * sizeof *v);
    memcpy(v + 60, p + 3 * 4, 3 * sizeof *v);   /* vertex 20 repeats vertex 4 */
    memcpy(v + 63, p + 3 * 11, 3 * sizeof *v);  /* vertex 21 repeats vertex 11 */
    gtet_check_report r;
    gtet_status st = gtet_check_arrays(v, 22, a.t, a.nt, NULL, v, 22, GTET_CHECK_FULL, &r);
    TEST_CHECK(st == GTET_OK && r.unused_vertices == 2 && r.duplicates == 2, "copies: %s", r.message);
    v[63] += 0.5;  /* vertex 21 is now a point of its own, in no tet */
    st = gtet_check_arrays(v, 22, a.t, a.nt, NULL, NULL, 0, GTET_CHECK_DELAUNAY, &r);
    TEST_CHECK(st == GTET_ERR_CHECK_FAILED && strstr(r.message, "vertex 21") &&
                   strstr(r.message, "in no tet") && r.violation.nvertices == 1 &&
                   r.violation.vertex[0] == 21, "unused point: %s", r.message);
    tm_free(&a);
    free(p);
}

/* NOTES.md Q33: an identical pair is judged against the input points when they are given:
 * one point of the input moved (as a writer that rounds would), or a mesh that is not
 * Delaunay, is not "identical"; without input points the verdict stays the comparison's. */
static void test_identical_pair_is_checked_against_the_input(void)
{
    double *p = tm_random_points(11, 30);
    tmesh a = tm_brute_delaunay(p, 30);
    gtet_diff_report d;
    TEST_REQUIRE(gtet_diff(a.v, a.nv, a.t, a.nt, a.v, a.nv, a.t, a.nt, p, 30, &d) == GTET_OK, "%s",
                 d.message);
    TEST_CHECK(d.kind == GTET_DIFF_IDENTICAL, "the input itself: %s", d.message);
    gtet_diff_report_free(&d);
    double q[90];
    memcpy(q, p, sizeof q);
    q[3 * 7 + 1] *= 1 + 1e-12;  /* the input differs from both meshes in one coordinate */
    TEST_REQUIRE(gtet_diff(a.v, a.nv, a.t, a.nt, a.v, a.nv, a.t, a.nt, q, 30, &d) == GTET_OK, "%s",
                 d.message);
    TEST_CHECK(d.kind == GTET_DIFF_NEITHER_DELAUNAY && !d.check_a.ok && !d.check_b.ok &&
                   strstr(d.message, "identical, and neither is a Delaunay mesh of the input"),
               "a moved input point: %d %s", (int)d.kind, d.message);
    gtet_diff_report_free(&d);
    TEST_REQUIRE(gtet_diff(a.v, a.nv, a.t, a.nt, a.v, a.nv, a.t, a.nt, NULL, 0, &d) == GTET_OK, "%s",
                 d.message);
    TEST_CHECK(d.kind == GTET_DIFF_IDENTICAL, "no input: %s", d.message);
    gtet_diff_report_free(&d);
    /* the same mesh with a tet missing on both sides: identical, but no tetrahedrization of
     * the input (the checker names the hole) */
    TEST_REQUIRE(gtet_diff(a.v, a.nv, a.t, a.nt - 1, a.v, a.nv, a.t, a.nt - 1, p, 30, &d) == GTET_OK,
                 "%s", d.message);
    TEST_CHECK(d.kind == GTET_DIFF_NEITHER_DELAUNAY, "a tet missing on both sides: %s", d.message);
    gtet_diff_report_free(&d);
    tm_free(&a);
    free(p);
}

int main(void)
{
    TU_RUN(test_both_cube_splits_are_delaunay_and_differ_by_one_group);
    TU_RUN(test_two_cubes_give_two_groups);
    TU_RUN(test_flat_bipyramid_in_two_tets_fails_both_modes);
    TU_RUN(test_renumbered_reoriented_copy_is_identical_and_moved_point_is_not);
    TU_RUN(test_unused_copies_are_accepted_and_unused_points_are_not);
    TU_RUN(test_identical_pair_is_checked_against_the_input);
    return tu_finish();
}
