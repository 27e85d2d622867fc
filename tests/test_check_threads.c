/* test_check_threads.c -- the exact checker's verdict and its first-violation message do not
 * depend on the number of OpenMP threads.  Its parallel stages (orientation, facet matching,
 * edge counts, local Delaunay, the volume sum) each report the violation with the smallest
 * index; a mesh corrupted at several places far apart (so that different threads meet
 * different violations) must give the same report with 1, 2 and 3 threads, and the reported
 * one must be the first.  The meshes have about 26000 tets, above the size at which the
 * stages go parallel.
 */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gigatet.h"
#include "testutil.h"

typedef struct arrays {
    double *v;
    size_t nv;
    uint32_t *t, *nb;
    size_t nt;
    double *xyz;
    size_t n;
} arrays;

static arrays base(void)
{
    arrays a = {0};
    tu_rng r = {20261122};
    a.n = 4000;
    a.xyz = malloc(3 * a.n * sizeof *a.xyz);
    for (size_t i = 0; i < 3 * a.n; i++) a.xyz[i] = tu_uniform(&r);
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 1;
    gtet_mesh *m = NULL;
    if (gtet_triangulate(a.xyz, a.n, &o, &m) != GTET_OK) return a;
    a.nv = gtet_mesh_num_vertices(m);
    a.nt = gtet_mesh_num_tets(m);
    a.v = malloc(3 * a.nv * sizeof *a.v);
    a.t = malloc(4 * a.nt * sizeof *a.t);
    a.nb = malloc(4 * a.nt * sizeof *a.nb);
    memcpy(a.v, gtet_mesh_vertices(m), 3 * a.nv * sizeof *a.v);
    memcpy(a.t, gtet_mesh_tets(m), 4 * a.nt * sizeof *a.t);
    memcpy(a.nb, gtet_mesh_neighbors(m), 4 * a.nt * sizeof *a.nb);
    gtet_mesh_free(&m);
    return a;
}

static void release(arrays *a)
{
    free(a->v);
    free(a->t);
    free(a->nb);
    free(a->xyz);
}

/* Check with 1, 2 and 3 threads; require identical status and report; return the status and
 * leave the 1-thread message in msg. */
static gtet_status check_all_counts(const arrays *a, int with_nb, int with_input, char msg[512])
{
    gtet_check_report r1, rk;
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    gtet_status s1 = gtet_check_arrays(a->v, a->nv, a->t, a->nt, with_nb ? a->nb : NULL,
                                       with_input ? a->xyz : NULL, with_input ? a->n : 0, 0, &r1);
    for (int k = 2; k <= 3; k++) {
        omp_set_num_threads(k);
        gtet_status sk = gtet_check_arrays(a->v, a->nv, a->t, a->nt, with_nb ? a->nb : NULL,
                                           with_input ? a->xyz : NULL, with_input ? a->n : 0, 0,
                                           &rk);
        TEST_CHECK(sk == s1, "status %d with %d threads, %d with 1", (int)sk, k, (int)s1);
        TEST_CHECK(!strcmp(rk.message, r1.message), "%d threads: '%s'\n  1 thread: '%s'", k,
                   rk.message, r1.message);
        TEST_CHECK(rk.ok == r1.ok && rk.euler == r1.euler && rk.hull_facets == r1.hull_facets &&
                       rk.facets_checked == r1.facets_checked && rk.duplicates == r1.duplicates,
                   "report fields differ with %d threads", k);
    }
    omp_set_num_threads(saved);
    snprintf(msg, 512, "%s", r1.message);
    return s1;
}

static void test_a_valid_mesh_gets_the_same_report_for_any_thread_count(void)
{
    arrays a = base();
    TEST_REQUIRE(a.t && a.nt > 20000, "the base mesh has %zu tets", a.nt);
    char msg[512];
    TEST_CHECK(check_all_counts(&a, 1, 1, msg) == GTET_OK, "%s", msg);
    release(&a);
}

static void test_several_negative_tets_report_the_smallest_for_any_thread_count(void)
{
    arrays a = base();
    TEST_REQUIRE(a.t && a.nt > 20000, "the base mesh has %zu tets", a.nt);
    size_t bad[3] = {a.nt - 5, a.nt / 2 + 1, a.nt / 3 + 7};
    for (int i = 0; i < 3; i++) {
        uint32_t *q = a.t + 4 * bad[i], x = q[0];
        q[0] = q[1];
        q[1] = x;
    }
    char msg[512], want[64];
    TEST_CHECK(check_all_counts(&a, 0, 0, msg) == GTET_ERR_CHECK_FAILED, "passed");
    snprintf(want, sizeof want, "tet %zu (", a.nt / 3 + 7);
    TEST_CHECK(strstr(msg, want) && strstr(msg, "negatively oriented"), "got '%s'", msg);
    release(&a);
}

static void test_several_repeated_tets_give_the_same_report_for_any_thread_count(void)
{
    arrays a = base();
    TEST_REQUIRE(a.t && a.nt > 20000, "the base mesh has %zu tets", a.nt);
    /* tet j becomes a copy of tet i: a facet in 3 tets or a repeated tet, in several buckets */
    size_t pairs[3][2] = {{a.nt - 3, 10}, {a.nt / 2 + 100, a.nt / 2}, {a.nt / 4, a.nt - 40}};
    for (int i = 0; i < 3; i++) memcpy(a.t + 4 * pairs[i][0], a.t + 4 * pairs[i][1], 16);
    char msg[512];
    TEST_CHECK(check_all_counts(&a, 0, 0, msg) == GTET_ERR_CHECK_FAILED, "passed");
    TEST_CHECK(strstr(msg, "same four vertices") || strstr(msg, "is in 3 tets") ||
                   strstr(msg, "is in no tet"), "got '%s'", msg);
    release(&a);
}

static void test_moved_vertices_give_the_same_report_for_any_thread_count(void)
{
    arrays a = base();
    TEST_REQUIRE(a.t && a.nt > 20000, "the base mesh has %zu tets", a.nt);
    /* small moves of many vertices: several facets stop being locally Delaunay (or a tet
     * flips), found by different threads */
    int failed = 0;
    for (int round = 0; round < 3; round++) {
        for (size_t v = (size_t)round; v < a.nv; v += 97)
            for (int j = 0; j < 3; j++) a.v[3 * v + j] += 1e-3 * (j - 1);
        char msg[512];
        gtet_status st = check_all_counts(&a, 0, 0, msg);
        failed += st == GTET_ERR_CHECK_FAILED;
        if (st == GTET_ERR_CHECK_FAILED)
            TEST_CHECK(strstr(msg, "not locally Delaunay") || strstr(msg, "oriented") ||
                           strstr(msg, "flat") || strstr(msg, "hull") || strstr(msg, "volume"),
                       "got '%s'", msg);
    }
    TEST_CHECK(failed == 3, "only %d of 3 rounds of moves were caught", failed);
    release(&a);
}

static void test_broken_links_give_the_same_report_for_any_thread_count(void)
{
    arrays a = base();
    TEST_REQUIRE(a.t && a.nt > 20000, "the base mesh has %zu tets", a.nt);
    a.nb[4 * (a.nt - 2) + 1] = 0;
    a.nb[4 * (a.nt / 2) + 3] = 1;
    char msg[512];
    TEST_CHECK(check_all_counts(&a, 1, 1, msg) == GTET_ERR_CHECK_FAILED, "passed");
    TEST_CHECK(strstr(msg, "neighbor[4*") != NULL, "got '%s'", msg);
    release(&a);
}

int main(void)
{
    TU_RUN(test_a_valid_mesh_gets_the_same_report_for_any_thread_count);
    TU_RUN(test_several_negative_tets_report_the_smallest_for_any_thread_count);
    TU_RUN(test_several_repeated_tets_give_the_same_report_for_any_thread_count);
    TU_RUN(test_moved_vertices_give_the_same_report_for_any_thread_count);
    TU_RUN(test_broken_links_give_the_same_report_for_any_thread_count);
    return tu_finish();
}
