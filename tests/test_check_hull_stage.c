/* test_check_hull_stage.c -- the global half of the hull-convexity proof (check_geom.c, steps
 * (b) and (c)) can fail.  A hull surface that passes every local test but wraps twice around
 * the mesh (two copies of a tetrahedron's boundary) is rejected by the ray count; a hull that
 * does not contain tet 0 is rejected by the centroid test.  Such surfaces cannot be reached
 * through gtet_check_arrays() without first failing the Euler or link tests, so the stage is
 * driven directly on a hand-filled context (src/check/check_internal.h).
 */
#include <string.h>

#include "check/check_internal.h"
#include "testutil.h"

static const double V[24] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,          /* unit tet */
                             10, 10, 10, 11, 10, 10, 10, 11, 10, 10, 10, 11};  /* far copy */

typedef struct fixture {
    uint32_t tets[8];
    uint32_t hull[3 * 8], hull_tf[8], hull_adj[3 * 8];
    gtet_check_report report;
    chk_ctx c;
} fixture;

/* copies of the boundary of tet `behind` (its four outward facets), each copy adjacent only to
 * itself; tet 0 is `first`. */
static void setup(fixture *x, int copies, const uint32_t first[4], uint32_t behind)
{
    memset(x, 0, sizeof *x);
    const uint32_t unit[4] = {0, 1, 2, 3};
    memcpy(x->tets, first, sizeof unit);
    memcpy(x->tets + 4, unit, sizeof unit);
    size_t nh = 0;
    for (int k = 0; k < copies; k++)
        for (int f = 0; f < 4; f++) {
            chk_outward_facet(x->tets + 4 * behind, f, x->hull + 3 * nh);
            x->hull_tf[nh++] = 4 * behind + (uint32_t)f;
        }
    for (size_t h = 0; h < nh; h++)
        for (int i = 0; i < 3; i++) {
            uint32_t a = x->hull[3 * h + i], b = x->hull[3 * h + (i + 1) % 3];
            for (size_t g = 4 * (h / 4); g < 4 * (h / 4) + 4; g++)
                for (int j = 0; j < 3; j++)
                    if (x->hull[3 * g + j] == b && x->hull[3 * g + (j + 1) % 3] == a)
                        x->hull_adj[3 * h + i] = (uint32_t)g;
        }
    x->c.vertices = V;
    x->c.nv = 8;
    x->c.tets = x->tets;
    x->c.nt = 2;
    x->c.hull = x->hull;
    x->c.hull_tf = x->hull_tf;
    x->c.hull_adj = x->hull_adj;
    x->c.nh = nh;
    x->c.report = &x->report;
}

static void test_a_simple_convex_hull_passes_the_stage(void)
{
    fixture x;
    const uint32_t unit[4] = {0, 1, 2, 3};
    setup(&x, 1, unit, 1);
    TEST_CHECK(chk_hull_convex(&x.c) == GTET_OK, "%s", x.report.message);
}

static void test_a_hull_wrapping_twice_is_caught_by_the_ray_count(void)
{
    fixture x;
    const uint32_t unit[4] = {0, 1, 2, 3};
    setup(&x, 2, unit, 1);
    TEST_CHECK(chk_hull_convex(&x.c) == GTET_ERR_CHECK_FAILED, "double hull passes");
    TEST_CHECK(strstr(x.report.message, "meets 2 hull facets, not 1") != NULL, "%s", x.report.message);
}

static void test_a_hull_missing_tet_0_is_caught_by_the_centroid_test(void)
{
    fixture x;
    const uint32_t far[4] = {4, 5, 6, 7};
    setup(&x, 1, far, 1);
    TEST_CHECK(chk_hull_convex(&x.c) == GTET_ERR_CHECK_FAILED, "foreign hull passes");
    TEST_CHECK(strstr(x.report.message, "centroid of tet 0 is not strictly inside") != NULL, "%s",
               x.report.message);
}

int main(void)
{
    TU_RUN(test_a_simple_convex_hull_passes_the_stage);
    TU_RUN(test_a_hull_wrapping_twice_is_caught_by_the_ray_count);
    TU_RUN(test_a_hull_missing_tet_0_is_caught_by_the_centroid_test);
    return tu_finish();
}
