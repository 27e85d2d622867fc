/* test_parallel_flat.c -- a round's first pass on a flat shell keeps both threads inserting, and
 * the mesh does not depend on the partition (NOTES.md E70, src/kernel/parallel.c
 * first_pass_axis, src/kernel/slabs.c kpar_crossing / kpar_first_axis).
 *
 * Points on an ellipsoid with half-axes 1, 1, 1/4: the Delaunay mesh's inside is long flat tets
 * from the lower to the upper surface.  With two threads the Moore curve's two slices were
 * split by the plane z = 0 (its top-level cut runs across the thin axis), which every one of
 * those tets crosses: the first pass of every round inserted ~0 points (200k points: first-pass
 * alpha 0.0000 / 0.0001 / 0.0000, all went serial).  Median slabs across x or y are crossed by
 * ~1/100 as many tets; the first pass takes them (0.86 / 0.95 / 0.98).
 *
 * Specification: for these points, 2 threads: at least one round runs on 2 threads, and every
 * such round's first pass inserts at least half its points; 1, 2 and 3 threads give the same
 * tets (the output is the unique perturbed Delaunay mesh, whatever the slices: a partition
 * that let two threads touch one tet, or lost a point, would show here or in the sanitized
 * builds).  Under ASan / TSan the set is 40k points (rounds still above 2 x 2048 points).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "canon.h"
#include "gigatet.h"
#include "testutil.h"

#ifdef GTET_TEST_SANITIZED
enum { N = 40000 };
#else
enum { N = 120000 };
#endif

/* n points on the ellipsoid x^2 + y^2 + (4z)^2 = 1 (normalized Gaussian directions, z / 4). */
static double *flat_shell(size_t n, uint64_t seed)
{
    double *p = malloc(3 * n * sizeof *p);
    tu_rng r = {seed};
    for (size_t i = 0; p && i < n; i++) {
        double g[3], len = 0;
        do {
            len = 0;
            for (int d = 0; d < 3; d++) {
                const double u1 = tu_uniform(&r) + 0x1p-60, u2 = tu_uniform(&r);
                g[d] = sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
                len += g[d] * g[d];
            }
        } while (len < 1e-12);
        len = sqrt(len);
        p[3 * i] = g[0] / len;
        p[3 * i + 1] = g[1] / len;
        p[3 * i + 2] = 0.25 * g[2] / len;
    }
    return p;
}

/* The canonical tets (ids form) of p with `threads`; with 2 threads also the first-pass check. */
static uint32_t *run(const double *p, size_t n, int threads, size_t *nt)
{
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    o.threads = threads;
    o.error = &err;
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(p, n, &o, &m);
    if (s != GTET_OK) {
        tu_fail(__FILE__, __LINE__, "%d threads: status %d: %s", threads, (int)s, err.message);
        return NULL;
    }
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    int parallel_rounds = 0;
    for (int k = 0; threads == 2 && k < st.num_rounds; k++) {
        const gtet_round_stats *rs = &st.rounds[k];
        if (rs->threads < 2 && rs->passes < 2) continue;  /* a serial round */
        parallel_rounds++;
        TEST_CHECK(rs->alpha_first >= 0.5,
                   "round %d (%llu points): the first pass on 2 threads inserted only %.4f", k,
                   (unsigned long long)rs->points, rs->alpha_first);
    }
    TEST_CHECK(threads != 2 || parallel_rounds >= 1, "no round ran on 2 threads");
    *nt = gtet_mesh_num_tets(m);
    char why[160];
    uint32_t *c = canon_input_ids(m, NULL, n, why);
    gtet_mesh_free(&m);
    TEST_CHECK(c != NULL, "%s", why);
    return c;
}

static void test_a_flat_shell_keeps_both_threads_and_its_mesh(void)
{
    double *p = flat_shell(N, 3);
    TEST_REQUIRE(p != NULL, "out of memory");
    size_t nt1 = 0;
    uint32_t *ref = run(p, N, 1, &nt1);
    for (int threads = 2; ref && threads <= 3; threads++) {
        size_t nt = 0;
        uint32_t *c = run(p, N, threads, &nt);
        TEST_CHECK(c && nt == nt1 && memcmp(c, ref, 4 * nt * sizeof *c) == 0,
                   "%d threads give other tets (%zu vs %zu)", threads, nt, nt1);
        free(c);
    }
    free(ref);
    free(p);
}

int main(void)
{
    TU_RUN(test_a_flat_shell_keeps_both_threads_and_its_mesh);
    return tu_finish();
}
