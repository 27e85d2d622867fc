/* test_check_valid.c -- the exact checker accepts valid perturbed Delaunay meshes, and among the
 * triangulations of a degenerate point set (cube corners, octahedron) exactly the perturbed
 * Delaunay one.
 *
 * References are built without the kernel: by hand, or by the brute-force definition in
 * test_check_meshes.h.  Every test asserts both ways: the right mesh passes, the other
 * triangulations of the same points fail with a local-Delaunay or hull-rule message.
 */
#include <stdio.h>
#include <string.h>

#include "test_check_meshes.h"
#include "testutil.h"

static int passes(const tmesh *m, const double *xyz, size_t n, unsigned flags, char *msg)
{
    gtet_check_report r;
    gtet_status st = tm_check(m, xyz, n, flags, &r);
    if (msg) snprintf(msg, 512, "%s", r.message);
    return st == GTET_OK && r.ok;
}

static void test_single_tet_is_valid_with_and_without_neighbors(void)
{
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t t[4] = {0, 1, 2, 3};
    tmesh m = tm_make(v, 4, t, 1);
    gtet_check_report r;
    TEST_CHECK(tm_check(&m, v, 4, GTET_CHECK_FULL, &r) == GTET_OK, "single tet: %s", r.message);
    TEST_CHECK(r.ok && r.tets == 1 && r.hull_facets == 4 && r.euler == 1 && r.duplicates == 0,
               "report: ok %d tets %llu hull %llu euler %d", r.ok, (unsigned long long)r.tets,
               (unsigned long long)r.hull_facets, r.euler);
    TEST_CHECK(r.facets_checked == 4, "facets_checked %llu", (unsigned long long)r.facets_checked);
    TEST_CHECK(gtet_check_arrays(v, 4, t, 1, NULL, NULL, 0, 0, &r) == GTET_OK, "no neighbors: %s",
               r.message);
    TEST_CHECK(gtet_check_arrays(v, 4, t, 1, NULL, NULL, 0, 0, NULL) == GTET_OK, "NULL report");
    tm_free(&m);
}

static void test_input_duplicates_with_signed_zeros_are_counted(void)
{
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double xyz[21] = {0, 0, 0, 1, 0, 0, -0.0, 0, -0.0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, -0.0, 1};
    const uint32_t t[4] = {0, 1, 2, 3};
    tmesh m = tm_make(v, 4, t, 1);
    gtet_check_report r;
    TEST_CHECK(tm_check(&m, xyz, 7, 0, &r) == GTET_OK, "%s", r.message);
    TEST_CHECK(r.duplicates == 3, "expected 3 duplicates, got %llu", (unsigned long long)r.duplicates);
    tm_free(&m);
}

static void cube_points(double v[24])
{
    for (int i = 0; i < 8; i++) {
        v[3 * i] = (double)(i & 1);
        v[3 * i + 1] = (double)((i >> 1) & 1);
        v[3 * i + 2] = (double)((i >> 2) & 1);
    }
}

/* Nine triangulations of the cube, corners numbered x + 2y + 4z: 0-1 the two 5-tet splits (a
 * central tet of even or odd corners); 2-5 the four 6-tet splits around a main diagonal; 6-8 the
 * corner tets at 0 and 7 plus the octahedron 1..6 split around one of its diagonals (1,6),
 * (2,5), (3,4).  Split 6 is the perturbed Delaunay one: corner 0 ranks lowest and 7 highest. */
static tmesh cube_split(int which)
{
    double v[24];
    cube_points(v);
    uint32_t t[24];
    size_t nt;
    if (which < 2) {
        static const uint32_t five[2][20] = {
            {0, 3, 5, 6, 1, 0, 3, 5, 2, 0, 3, 6, 4, 0, 5, 6, 7, 3, 5, 6},
            {1, 2, 4, 7, 0, 1, 2, 4, 3, 1, 2, 7, 5, 1, 4, 7, 6, 2, 4, 7}};
        memcpy(t, five[which], sizeof five[which]);
        nt = 5;
    } else if (which >= 6) {
        static const uint32_t diag[3][2] = {{1, 6}, {2, 5}, {3, 4}};
        static const uint32_t ring[3][4] = {{2, 3, 5, 4}, {1, 3, 6, 4}, {1, 2, 6, 5}};
        static const uint32_t corners[8] = {0, 1, 2, 4, 7, 3, 5, 6};
        memcpy(t, corners, sizeof corners);
        for (int k = 0; k < 4; k++) {
            t[8 + 4 * k] = diag[which - 6][0];
            t[8 + 4 * k + 1] = diag[which - 6][1];
            t[8 + 4 * k + 2] = ring[which - 6][k];
            t[8 + 4 * k + 3] = ring[which - 6][(k + 1) % 4];
        }
        nt = 6;
    } else {
        /* diagonal (d, 7-d); the other six corners form a cycle of cube edges */
        static const uint32_t diag[4] = {0, 1, 2, 3};
        static const uint32_t ring[4][6] = {
            {1, 3, 2, 6, 4, 5}, {0, 2, 3, 7, 5, 4}, {0, 1, 3, 7, 6, 4}, {1, 0, 2, 6, 7, 5}};
        uint32_t d = diag[which - 2];
        for (int k = 0; k < 6; k++) {
            t[4 * k] = d;
            t[4 * k + 1] = 7 - d;
            t[4 * k + 2] = ring[which - 2][k];
            t[4 * k + 3] = ring[which - 2][(k + 1) % 6];
        }
        nt = 6;
    }
    return tm_make(v, 8, t, nt);
}

static void test_cube_only_the_perturbed_delaunay_split_passes(void)
{
    double v[24];
    cube_points(v);
    tmesh ref = tm_brute_delaunay(v, 8);
    char msg[512];
    TEST_CHECK(passes(&ref, v, 8, GTET_CHECK_FULL, msg), "brute-force cube mesh fails: %s", msg);
    int matched = 0;
    for (int w = 0; w < 9; w++) {
        tmesh m = cube_split(w);
        /* every split tiles the cube: only the Delaunay property can tell them apart */
        int ok = passes(&m, v, 8, 0, msg);
        int same = tm_same_tets(&m, &ref);
        matched += same;
        TEST_CHECK(ok == same, "cube split %d: checker says %s (%s), brute force says %s", w,
                   ok ? "valid" : "invalid", msg, same ? "Delaunay" : "not Delaunay");
        if (!same) {
            /* the cube's 8 corners are co-spherical: a wrong split is a tie broken the other
             * way, and the report says so with the whole group */
            gtet_check_report r;
            tm_check(&m, v, 8, 0, &r);
            TEST_CHECK(strstr(msg, "not locally Delaunay") && strstr(msg, "a tie broken against") && r.violation.tie == 1 &&
                           r.violation.group_size == 8 && r.violation.nvertices == 5 &&
                           r.violation.tet[0] != GTET_CHECK_NONE &&
                           !strcmp(r.violation.stage, "delaunay"),
                       "cube split %d fails for another reason: %s", w, msg);
        }
        /* every split is a Delaunay triangulation in the closed sense */
        TEST_CHECK(passes(&m, v, 8, GTET_CHECK_DELAUNAY | GTET_CHECK_FULL, msg),
                   "cube split %d fails --delaunay: %s", w, msg);
        tm_free(&m);
    }
    TEST_CHECK(matched == 1, "the perturbed Delaunay cube mesh (%zu tets) is %d of the 9 splits",
               ref.nt, matched);
    tmesh six = cube_split(6);
    TEST_CHECK(tm_same_tets(&six, &ref), "split 6 is not the perturbed Delaunay cube mesh");
    tm_free(&six);
    tm_free(&ref);
}

static void test_octahedron_only_one_diagonal_passes(void)
{
    const double v[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    tmesh ref = tm_brute_delaunay(v, 6);
    char msg[512];
    TEST_CHECK(ref.nt == 4, "brute-force octahedron has %zu tets", ref.nt);
    TEST_CHECK(passes(&ref, v, 6, GTET_CHECK_FULL, msg), "brute-force octahedron: %s", msg);
    int valid = 0;
    for (uint32_t d = 0; d < 3; d++) {
        /* the 4 tets around the diagonal (2d, 2d+1) */
        uint32_t ring[4], k = 0, t[16];
        for (uint32_t a = 0; a < 3; a++)
            if (a != d) {
                ring[k++] = 2 * a;
                ring[k++] = 2 * a + 1;
            }
        const uint32_t cyc[4] = {ring[0], ring[2], ring[1], ring[3]};
        for (int i = 0; i < 4; i++) {
            t[4 * i] = 2 * d;
            t[4 * i + 1] = 2 * d + 1;
            t[4 * i + 2] = cyc[i];
            t[4 * i + 3] = cyc[(i + 1) % 4];
        }
        tmesh m = tm_make(v, 6, t, 4);
        int ok = passes(&m, v, 6, 0, msg);
        TEST_CHECK(ok == tm_same_tets(&m, &ref), "diagonal %u: checker %d (%s)", d, ok, msg);
        valid += ok;
        tm_free(&m);
    }
    TEST_CHECK(valid == 1, "%d octahedron diagonals pass", valid);
    tm_free(&ref);
}

static void test_random_points_brute_force_delaunay_passes_full_check(void)
{
    for (uint64_t seed = 1; seed <= 6; seed++) {
        size_t n = 10 + 2 * seed;
        double *v = tm_random_points(seed, n);
        tmesh m = tm_brute_delaunay(v, n);
        gtet_check_report r;
        gtet_status st = tm_check(&m, v, n, GTET_CHECK_FULL, &r);
        TEST_CHECK(st == GTET_OK, "seed %llu (%zu points, %zu tets): %s", (unsigned long long)seed,
                   n, m.nt, r.message);
        TEST_CHECK(r.euler == 1 && r.tets == m.nt, "seed %llu: report", (unsigned long long)seed);
        tm_free(&m);
        free(v);
    }
}

/* Degenerate sets: a 3x3x2 integer grid (cospherical and coplanar groups everywhere) and
 * points on a sphere's integer lattice (3,4,5-type triples). */
static void test_degenerate_grids_brute_force_delaunay_passes_full_check(void)
{
    double g[3 * 18];
    size_t n = 0;
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 3; x++) {
                g[3 * n] = x;
                g[3 * n + 1] = y;
                g[3 * n + 2] = z;
                n++;
            }
    tmesh m = tm_brute_delaunay(g, n);
    char msg[512];
    TEST_CHECK(passes(&m, g, n, GTET_CHECK_FULL, msg), "grid (%zu tets): %s", m.nt, msg);
    tm_free(&m);
    /* integer points with x^2 + y^2 + z^2 = 25 */
    double s[3 * 64];
    n = 0;
    for (int x = -5; x <= 5; x++)
        for (int y = -5; y <= 5; y++)
            for (int z = -5; z <= 5; z++)
                if (x * x + y * y + z * z == 25 && n < 20 && (x + 2 * y + 3 * z) % 3 == 0) {
                    s[3 * n] = x;
                    s[3 * n + 1] = y;
                    s[3 * n + 2] = z;
                    n++;
                }
    TEST_REQUIRE(n >= 8, "only %zu sphere points", n);
    m = tm_brute_delaunay(s, n);
    TEST_CHECK(passes(&m, s, n, GTET_CHECK_FULL, msg), "cospherical (%zu points, %zu tets): %s", n,
               m.nt, msg);
    tm_free(&m);
}

int main(void)
{
    TU_RUN(test_single_tet_is_valid_with_and_without_neighbors);
    TU_RUN(test_input_duplicates_with_signed_zeros_are_counted);
    TU_RUN(test_cube_only_the_perturbed_delaunay_split_passes);
    TU_RUN(test_octahedron_only_one_diagonal_passes);
    TU_RUN(test_random_points_brute_force_delaunay_passes_full_check);
    TU_RUN(test_degenerate_grids_brute_force_delaunay_passes_full_check);
    return tu_finish();
}
