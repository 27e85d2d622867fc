/* test_api_threads.c -- gtet_triangulate gets every thread its stages ask OpenMP for, or runs
 * on fewer from the start (NOTES.md E184): the stages split their work by thread number, and a
 * team smaller than asked left work undone (a segfault in the validate stage's dedup).  OpenMP
 * gives fewer threads than num_threads asks when dyn-var is on (omp_set_dynamic, OMP_DYNAMIC),
 * inside a parallel region beyond max-active-levels (a user's own parallel loop over point
 * sets), and past OMP_THREAD_LIMIT (tests/cli/test_thread_limits.sh, an environment variable).
 * Each run here gives the same tets as a one-thread run and passes the checker; dyn-var is as
 * the caller set it afterwards. */
#include <omp.h>
#include <stdlib.h>

#include "gigatet.h"
#include "testutil.h"

/* 100k points: the validate stage's regions run from 65536 points on */
#define N 100000

static double *points(void)
{
    double *xyz = malloc(3 * N * sizeof *xyz);
    tu_rng rng = {11};
    for (size_t i = 0; xyz && i < 3 * N; i++) xyz[i] = tu_uniform(&rng);
    return xyz;
}

/* A run with `threads`; its tet count, the stats' thread count, and the check. */
static size_t run(const double *xyz, int threads, int *used, int *ok)
{
    gtet_options opt;
    gtet_error err;
    gtet_options_init(&opt);
    opt.threads = threads;
    opt.error = &err;
    opt.check = 1;
    gtet_mesh *m = NULL;
    *ok = gtet_triangulate(xyz, N, &opt, &m) == GTET_OK;
    gtet_stats st;
    gtet_mesh_stats(m, &st);
    *used = st.threads;
    size_t nt = gtet_mesh_num_tets(m);
    gtet_mesh_free(&m);
    return nt;
}

static void dynamic_teams(void)
{
    double *xyz = points();
    TEST_REQUIRE(xyz != NULL, "allocation");
    int used, ok;
    const size_t ref = run(xyz, 1, &used, &ok);
    TEST_REQUIRE(ok, "one thread");
    /* dyn-var on gives at most the processors' count (less under load): ask for more */
    const int ask = omp_get_num_procs() + 6;
    omp_set_dynamic(1);
    TEST_CHECK(run(xyz, ask, &used, &ok) == ref && ok, "dynamic, %d threads", ask);
    TEST_CHECK(used == ask, "dynamic: %d threads used of %d", used, ask);
    TEST_CHECK(omp_get_dynamic(), "dyn-var not restored");
    omp_set_dynamic(0);
    free(xyz);
}

static void inside_a_parallel_region(void)
{
    double *xyz = points();
    TEST_REQUIRE(xyz != NULL, "allocation");
    int used0, ok0;
    const size_t ref = run(xyz, 1, &used0, &ok0);
    TEST_REQUIRE(ok0, "one thread");
    omp_set_max_active_levels(1);  /* no nesting: a region inside is inactive, one thread */
    size_t nt[2] = {0, 0};
    int used[2] = {0, 0}, ok[2] = {0, 0};
#pragma omp parallel num_threads(2)
    {
        const int k = omp_get_thread_num();
        if (k < 2) nt[k] = run(xyz, 4, &used[k], &ok[k]);
    }
    for (int k = 0; k < 2; k++) {
        TEST_CHECK(ok[k] && nt[k] == ref, "caller thread %d: ok %d, %zu tets of %zu", k, ok[k],
                   nt[k], ref);
        TEST_CHECK(used[k] == 1, "caller thread %d: %d threads in an inactive region", k,
                   used[k]);
    }
    /* with nesting allowed, each call's regions get the threads asked for */
    omp_set_max_active_levels(2);
#pragma omp parallel num_threads(2)
    {
        const int k = omp_get_thread_num();
        if (k < 2) nt[k] = run(xyz, 2, &used[k], &ok[k]);
    }
    for (int k = 0; k < 2; k++)
        TEST_CHECK(ok[k] && nt[k] == ref && used[k] == 2, "nested, thread %d: ok %d, %zu tets, "
                   "%d threads", k, ok[k], nt[k], used[k]);
    omp_set_max_active_levels(1);
    free(xyz);
}

int main(void)
{
    TU_RUN(dynamic_teams);
    TU_RUN(inside_a_parallel_region);
    return tu_finish();
}
