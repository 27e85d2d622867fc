/* test_api_cancel.c -- gtet_options.cancel: polled between BRIO rounds on the calling thread;
 * a nonzero answer stops the run with GTET_ERR_CANCELLED, no mesh and the error filled; a hook
 * that never stops changes nothing. */
#include <stdlib.h>

#include "gigatet.h"
#include "testutil.h"

typedef struct poll_state {
    int calls;
    int stop_at;  /* answer 1 from this call on (counting from 1); 0: never */
} poll_state;

static int poll_hook(void *user)
{
    poll_state *p = user;
    p->calls++;
    return p->stop_at && p->calls >= p->stop_at;
}

static void cancel_at_every_round(int threads)
{
    const size_t n = 100000;
    double *xyz = malloc(3 * n * sizeof *xyz);
    TEST_REQUIRE(xyz != NULL, "allocation");
    tu_rng rng = {7};
    for (size_t i = 0; i < 3 * n; i++) xyz[i] = tu_uniform(&rng);
    gtet_options opt;
    gtet_error err;
    gtet_options_init(&opt);
    TEST_CHECK(opt.cancel == NULL && opt.cancel_user == NULL, "cancel defaults to NULL");
    opt.threads = threads;
    opt.error = &err;
    poll_state never = {0, 0};
    opt.cancel = poll_hook;
    opt.cancel_user = &never;
    gtet_mesh *ref = NULL;
    TEST_CHECK(gtet_triangulate(xyz, n, &opt, &ref) == GTET_OK, "a hook that never stops");
    gtet_stats st;
    gtet_mesh_stats(ref, &st);
    TEST_CHECK(never.calls == st.num_rounds && never.calls >= 2, "%d polls for %d rounds",
               never.calls, st.num_rounds);
    for (int stop = 1; stop <= never.calls; stop++) {
        poll_state p = {0, stop};
        opt.cancel_user = &p;
        gtet_mesh *mesh = NULL;
        gtet_status s = gtet_triangulate(xyz, n, &opt, &mesh);
        TEST_CHECK(s == GTET_ERR_CANCELLED, "stop at poll %d: status %d", stop, (int)s);
        TEST_CHECK(mesh == NULL, "no mesh after a cancelled run");
        TEST_CHECK(err.status == GTET_ERR_CANCELLED && err.message[0],
                   "the error record says cancelled");
        TEST_CHECK(p.calls == stop, "polled %d times after a stop at %d", p.calls, stop);
    }
    opt.cancel = NULL;  /* a run after cancelled ones is the same */
    gtet_mesh *again = NULL;
    TEST_CHECK(gtet_triangulate(xyz, n, &opt, &again) == GTET_OK, "run after cancel");
    TEST_CHECK(again && ref && gtet_mesh_num_tets(again) == gtet_mesh_num_tets(ref), "same tets");
    gtet_mesh_free(&again);
    gtet_mesh_free(&ref);
    free(xyz);
}

static void test_cancel_one_thread(void) { cancel_at_every_round(1); }
static void test_cancel_two_threads(void) { cancel_at_every_round(2); }

int main(void)
{
    TU_RUN(test_cancel_one_thread);
    TU_RUN(test_cancel_two_threads);
    return tu_finish();
}
