/* test_api_input_done.c -- gtet_options.input_done: called exactly once, when the run no longer
 * reads the caller's points (after the validate stage; with opts.check, after the check), so
 * that a caller may free them.  The hook here overwrites the whole array with NaN: any later
 * read would change the mesh or fail the run.  A run that fails in validation never calls it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "canon.h"
#include "gigatet.h"
#include "testutil.h"

typedef struct hook_state {
    double *xyz;
    size_t n;
    int calls;
} hook_state;

static void poison(void *user)
{
    hook_state *h = user;
    h->calls++;
    for (size_t i = 0; i < 3 * h->n; i++) h->xyz[i] = NAN;
}

/* n points in the unit cube, every tenth a copy of an earlier one (the input map matters) */
static double *make_points(size_t n, uint64_t seed)
{
    double *xyz = malloc(3 * n * sizeof *xyz);
    if (!xyz) return NULL;
    tu_rng rng = {seed};
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && i % 10 == 0) memcpy(xyz + 3 * i, xyz + 3 * tu_below(&rng, i), 3 * sizeof *xyz);
        else for (int k = 0; k < 3; k++) xyz[3 * i + k] = tu_uniform(&rng);
    }
    return xyz;
}

/* The same vertices, input map and tets (as sorted id lists: with threads the tets' order
 * is not fixed, their set is). */
static uint32_t *sorted_tets(const gtet_mesh *m)
{
    const size_t nt = gtet_mesh_num_tets(m);
    uint32_t *t = malloc((nt ? 4 * nt : 1) * sizeof *t);
    if (!t) return NULL;
    memcpy(t, gtet_mesh_tets(m), 4 * nt * sizeof *t);
    canon_sort_ids(t, nt);
    return t;
}

static int same_mesh(const gtet_mesh *a, const gtet_mesh *b)
{
    const size_t nv = gtet_mesh_num_vertices(a), nt = gtet_mesh_num_tets(a);
    if (nv != gtet_mesh_num_vertices(b) || nt != gtet_mesh_num_tets(b) ||
        gtet_mesh_num_points(a) != gtet_mesh_num_points(b) ||
        memcmp(gtet_mesh_vertices(a), gtet_mesh_vertices(b), 3 * nv * sizeof(double)) ||
        memcmp(gtet_mesh_input_map(a), gtet_mesh_input_map(b),
               gtet_mesh_num_points(a) * sizeof(uint32_t)))
        return 0;
    uint32_t *ta = sorted_tets(a), *tb = sorted_tets(b);
    const int same = ta && tb && !memcmp(ta, tb, 4 * nt * sizeof *ta);
    free(ta);
    free(tb);
    return same;
}

static void poisoned_after_release(int threads, int check)
{
    const size_t n = 60000;
    double *xyz = make_points(n, 11);
    TEST_REQUIRE(xyz != NULL, "allocation");
    gtet_options opt;
    gtet_options_init(&opt);
    TEST_CHECK(opt.input_done == NULL && opt.input_done_user == NULL, "input_done defaults to NULL");
    opt.threads = threads;
    opt.check = check;
    gtet_mesh *ref = NULL;
    TEST_REQUIRE(gtet_triangulate(xyz, n, &opt, &ref) == GTET_OK, "run without the hook");
    hook_state h = {xyz, n, 0};
    opt.input_done = poison;
    opt.input_done_user = &h;
    gtet_error err;
    opt.error = &err;
    gtet_mesh *mesh = NULL;
    gtet_status s = gtet_triangulate(xyz, n, &opt, &mesh);
    TEST_CHECK(s == GTET_OK, "threads %d check %d: status %d (%s)", threads, check, (int)s,
               err.message);
    TEST_CHECK(h.calls == 1, "threads %d check %d: called %d times", threads, check, h.calls);
    TEST_CHECK(mesh && same_mesh(ref, mesh),
               "threads %d check %d: the points were read after input_done", threads, check);
    gtet_mesh_free(&mesh);
    gtet_mesh_free(&ref);
    free(xyz);
}

static void test_released_one_thread(void) { poisoned_after_release(1, 0); }
static void test_released_two_threads(void) { poisoned_after_release(2, 0); }
static void test_released_after_check(void) { poisoned_after_release(2, 1); }

static void test_not_called_on_bad_input(void)
{
    const size_t n = 1000;
    double *xyz = make_points(n, 3);
    TEST_REQUIRE(xyz != NULL, "allocation");
    xyz[3 * 700 + 1] = INFINITY;
    hook_state h = {xyz, n, 0};
    gtet_options opt;
    gtet_options_init(&opt);
    opt.input_done = poison;
    opt.input_done_user = &h;
    gtet_mesh *mesh = NULL;
    TEST_CHECK(gtet_triangulate(xyz, n, &opt, &mesh) == GTET_ERR_NONFINITE, "infinite coordinate");
    TEST_CHECK(h.calls == 0 && mesh == NULL, "called %d times on a failed validation", h.calls);
    TEST_CHECK(xyz[0] == xyz[0], "the caller's points were left alone");
    free(xyz);
}

int main(void)
{
    TU_RUN(test_released_one_thread);
    TU_RUN(test_released_two_threads);
    TU_RUN(test_released_after_check);
    TU_RUN(test_not_called_on_bad_input);
    return tu_finish();
}
