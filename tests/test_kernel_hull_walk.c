/* test_kernel_hull_walk.c -- the walk over the hull (src/kernel/locate.c km_hull_search,
 * NOTES.md E60) that locates a point outside the hull after an insertion from outside it.
 *
 * Specification: on a convex hull around the centre o of the points' bounding box, the walk
 * from any ghost reaches, within its step budget, a ghost whose finite facet the point is
 * strictly beyond (exact orient3d > 0 in the ghost's facet order, kmesh.h), for every point
 * outside the hull; for a point inside the hull it finds nothing (no ghost conflicts).  The
 * hull here is that of 100 points on the unit sphere (196 facets), whose central projection
 * from o is the spherical Delaunay triangulation, so a visibility walk in it cannot cycle.
 * A walk that crossed the wrong edges (a sign flipped) or E32's breadth-first search of 8
 * ghosts would miss from the far side of the sphere.
 */
#include <math.h>

#include "kernel/conflict.h"
#include "testutil.h"

#define NS 100   /* points on the unit sphere, inserted */
#define NQ 40    /* query points: 20 outside (radius 1.25), 20 inside (radius 0.5) */

static void on_sphere(tu_rng *r, double radius, double *p)
{
    double n2;
    do {
        for (int j = 0; j < 3; j++) p[j] = 2 * tu_uniform(r) - 1;
        n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    } while (n2 < 0.01 || n2 > 1);
    const double s = radius / sqrt(n2);
    for (int j = 0; j < 3; j++) p[j] *= s;
}

static void test_hull_walk_finds_a_visible_facet_from_every_ghost(void)
{
    static double pts[NS + NQ][3];
    tu_rng r = {2026};
    for (int i = 0; i < NS + NQ; i++)
        on_sphere(&r, i < NS ? 1.0 : i < NS + NQ / 2 ? 1.25 : 0.5, pts[i]);
    kmesh m;
    kctx c;
    TEST_REQUIRE(km_init(&m, &pts[0][0], NS + NQ, 4096, 1, 0) == GTET_OK, "km_init");
    kctx_init(&c, &m, 7);
    TEST_REQUIRE(km_first_tet(&c, 0, 1, 2, 3) == GTET_OK, "first tet");
    for (uint32_t i = 4; i < NS; i++) {
        int deferred = 0;
        TEST_REQUIRE(km_insert(&c, i, &deferred) == GTET_OK && !deferred, "insert %u", i);
    }
    long ghosts = 0, found = 0, wrong = 0, inside_found = 0;
    for (size_t g = 0; g < m.nt; g++) {
        if (km_dead(&m, g) || !km_is_ghost(&m, (uint32_t)g)) continue;
        ghosts++;
        for (uint32_t q = NS; q < NS + NQ; q++) {
            c.last_ghost = (uint32_t)g;
            const uint32_t h = km_hull_search(&c, pts[q]);
            if (q >= NS + NQ / 2) {
                inside_found += h != UINT32_MAX;
                continue;
            }
            if (h == UINT32_MAX) continue;
            found++;
            const uint32_t *v = m.tv + 4 * (size_t)h;
            pred_counters cnt = {0};
            wrong += km_dead(&m, h) || v[3] != KM_GHOST ||
                     pred_orient3d(km_pt(&m, v[0]), km_pt(&m, v[1]), km_pt(&m, v[2]), pts[q],
                                   &cnt) <= 0;
        }
    }
    TEST_CHECK(ghosts == 2 * NS - 4, "%ld ghosts, a closed hull of %d vertices has %d", ghosts,
               NS, 2 * NS - 4);
    TEST_CHECK(found == ghosts * (NQ / 2), "the hull walk found %ld of %ld (start, point) pairs",
               found, ghosts * (NQ / 2));
    TEST_CHECK(wrong == 0, "%ld ghosts returned that the point is not beyond", wrong);
    TEST_CHECK(inside_found == 0, "%ld ghosts returned for points inside the hull",
               inside_found);
    kctx_free(&c);
    km_free(&m);
}

int main(void)
{
    TU_RUN(test_hull_walk_finds_a_visible_facet_from_every_ghost);
    return tu_finish();
}
