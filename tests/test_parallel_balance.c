/* test_parallel_balance.c -- with two threads both threads insert on points of a sphere
 * (issue 18: the second thread must help on non-uniform inputs), judged by counters, not time.
 *
 * On `generate sphere` points the cavities and walks run through long tets between far
 * vertices.  A thread whose walk stood in a tet it could not leave without entering a tet of
 * the other colour deferred that point and, walking again from the same tet, every next one,
 * until it gave up on its slice: the pass inserted about half the round (one thread's slice)
 * and the rest went serial.  Now a thread whose last try was deferred restarts at the next of
 * 63 checkpoint tets located along its slice before the pass (find_checkpoints in
 * src/kernel/parallel.c; NOTES.md E13).
 *
 * Specification: for 200k sphere points, seeds 1 and 2, with 2 threads, every BRIO round whose
 * first pass ran on 2 threads inserts at least 0.65 of its points in that first pass (slices
 * are within 1/32 of equal, so each thread then inserted at least 0.3 of its own slice).
 * Before the checkpoints the worst such round's first pass inserted 0.30 (seed 1) and 0.20
 * (seed 2); now 0.74 and 0.75.  (gtet_round_stats has no per-thread counts; the first
 * pass's alpha is the public counter that shows a thread stopping.)  It runs in the
 * sanitized builds too (a few seconds under ASan).
 */
#include <stdlib.h>

#include "gigatet.h"
#include "io/io.h"
#include "testutil.h"

static void sphere_rounds_keep_both_threads_inserting(uint64_t seed)
{
    double *p = NULL;
    size_t n = 0;
    io_error ie;
    TEST_REQUIRE(io_generate("sphere", 200000, seed, &p, &n, &ie) == IO_OK, "generator");
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 2;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(p, n, &o, &m);
    free(p);
    TEST_REQUIRE(s == GTET_OK, "sphere seed %llu: status %d", (unsigned long long)seed, (int)s);
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    int parallel_rounds = 0;
    for (int r = 0; r < st.num_rounds; r++) {
        const gtet_round_stats *rs = &st.rounds[r];
        if (rs->threads < 2) continue;
        parallel_rounds++;
        TEST_CHECK(rs->alpha_first >= 0.65,
                   "sphere seed %llu, round %d (%llu points): the first pass inserted only %.3f",
                   (unsigned long long)seed, r, (unsigned long long)rs->points,
                   rs->alpha_first);
    }
    TEST_CHECK(parallel_rounds >= 2, "sphere seed %llu: %d rounds on 2 threads",
               (unsigned long long)seed, parallel_rounds);
    gtet_mesh_free(&m);
}

static void test_both_threads_insert_in_every_round_of_sphere_points(void)
{
    sphere_rounds_keep_both_threads_inserting(1);
    sphere_rounds_keep_both_threads_inserting(2);
}

int main(void)
{
    TU_RUN(test_both_threads_insert_in_every_round_of_sphere_points);
    return tu_finish();
}
