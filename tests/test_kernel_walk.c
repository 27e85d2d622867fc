/* test_kernel_walk.c -- the kernel's visibility walk (src/kernel/insert.c) started from a ghost
 * tet, the case a parallel pass meets when a thread's start tet is a ghost (parallel.c
 * find_start accepts ghosts of its colour) and the next point lies outside the hull.
 *
 * Specification: from a ghost, the walk must locate a tet in conflict with the point without
 * the linear-scan fallback (serial) and without an internal error (parallel pass, where there
 * is no fallback).  A walk that moved to the ghost's finite neighbour and skipped the hull
 * facet as if it had crossed it would "locate" a point beyond that facet in a tet whose
 * circumsphere does not contain it: an internal error with -t 2..4 and a linear scan per such
 * point with -t 1, on cospherical, sphere and paraboloid sets of 50k-200k points.
 */
#include <string.h>

#include "kernel/kmesh.h"
#include "testutil.h"

/* the unit corner tet, and p beyond its facet x + y + z = 1 (outside its circumsphere) */
static const double pts[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 2, 2}};

/* the ghost whose finite facet is {1, 2, 3} */
static uint32_t ghost_on_far_facet(const kmesh *m)
{
    for (uint32_t t = 0; t < m->nt; t++) {
        const uint32_t *v = m->tv + 4 * (size_t)t;
        if (v[3] != KM_GHOST) continue;
        int far = 1;
        for (int i = 0; i < 3; i++) far &= v[i] != 0;
        if (far) return t;
    }
    return UINT32_MAX;
}

/* live tets: adjacency symmetric; returns the number of live finite tets */
static long live_finite_and_links(const kmesh *m, long *bad)
{
    long finite = 0;
    for (size_t t = 0; t < m->nt; t++) {
        if (km_dead(m, t)) continue;
        if (m->tv[4 * t + 3] != KM_GHOST) finite++;
        for (size_t f = 0; f < 4; f++) {
            const uint32_t h = m->tn[4 * t + f];
            *bad += km_dead(m, h >> 2) || m->tn[h] != 4 * t + f;
        }
    }
    return finite;
}

static void run(int parallel)
{
    kmesh m;
    kctx c;
    uint8_t colour[5] = {0, 0, 0, 0, 0};
    TEST_REQUIRE(km_init(&m, &pts[0][0], 5, 8 * KM_SLOT_BLOCK, 1, 0) == GTET_OK, "km_init");
    kctx_init(&c, &m, 7);
    TEST_REQUIRE(km_first_tet(&c, 0, 1, 2, 3) == GTET_OK, "first tet");
    const uint32_t g = ghost_on_far_facet(&m);
    TEST_REQUIRE(g != UINT32_MAX, "no ghost on the facet {1,2,3}");
    c.last = g;
    if (parallel) {
        c.colour = colour;  /* one colour: every tet is this thread's */
        c.mine = 0;
    }
    int deferred = 1;
    const gtet_status s = km_insert(&c, 4, &deferred);
    TEST_CHECK(s == GTET_OK, "%s walk from a ghost: %s", parallel ? "parallel" : "serial",
               gtet_status_str(s));
    TEST_CHECK(!deferred, "deferred with no other colour");
    TEST_CHECK(c.walk_fallbacks == 0, "the walk fell back to a linear scan (%llu)",
               (unsigned long long)c.walk_fallbacks);
    if (parallel) km_flush_block(&c);
    long bad = 0;
    const long finite = live_finite_and_links(&m, &bad);
    TEST_CHECK(finite == 2, "%ld finite tets, expected 2 (p sees one hull facet)", finite);
    TEST_CHECK(bad == 0, "%ld broken neighbour links", bad);
    kctx_free(&c);
    km_free(&m);
}

static void test_walk_from_a_ghost_to_a_point_beyond_its_facet_serial(void) { run(0); }
static void test_walk_from_a_ghost_to_a_point_beyond_its_facet_in_a_parallel_pass(void) { run(1); }

int main(void)
{
    TU_RUN(test_walk_from_a_ghost_to_a_point_beyond_its_facet_serial);
    TU_RUN(test_walk_from_a_ghost_to_a_point_beyond_its_facet_in_a_parallel_pass);
    return tu_finish();
}
