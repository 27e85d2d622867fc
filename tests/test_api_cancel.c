/* test_api_cancel.c -- gtet_options.cancel: polled on the calling thread before each BRIO
 * round, before each pass of a round and every 65536 points of a one-thread pass; a nonzero
 * answer stops the run with GTET_ERR_CANCELLED, no mesh and the error filled, at whichever poll
 * it comes; a hook that never stops changes nothing.  The last (biggest) round is polled inside,
 * so Ctrl-C in Python is not held back for the whole of it. */
#include <stdlib.h>

#include "gigatet.h"
#include "testutil.h"

typedef struct poll_state {
    int calls;
    int stop_at;       /* answer 1 from this call on (counting from 1); 0: never */
    double fraction;   /* the last progress report */
    int in_last_round; /* polls made after the progress passed last_round_start */
    double last_round_start;
} poll_state;

static int poll_hook(void *user)
{
    poll_state *p = user;
    p->calls++;
    if (p->fraction > p->last_round_start) p->in_last_round++;
    return p->stop_at && p->calls >= p->stop_at;
}

static void progress_hook(void *user, double fraction)
{
    ((poll_state *)user)->fraction = fraction;
}

static void cancel_at_every_poll(int threads)
{
    const size_t n = 200000;
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
    gtet_mesh *ref = NULL;
    TEST_CHECK(gtet_triangulate(xyz, n, &opt, &ref) == GTET_OK, "no hook");
    gtet_stats st;
    gtet_mesh_stats(ref, &st);
    int passes = 0;
    for (int k = 0; k < st.num_rounds; k++) passes += st.rounds[k].passes;
    const gtet_round_stats *last = &st.rounds[st.num_rounds - 1];
    poll_state never = {0};
    never.last_round_start = (double)(n - last->points) / (double)n + 1e-9;
    opt.cancel = poll_hook;
    opt.cancel_user = &never;
    opt.progress = progress_hook;
    opt.progress_user = &never;
    gtet_mesh *hooked = NULL;
    TEST_CHECK(gtet_triangulate(xyz, n, &opt, &hooked) == GTET_OK, "a hook that never stops");
    TEST_CHECK(hooked && gtet_mesh_num_tets(hooked) == gtet_mesh_num_tets(ref), "same tets");
    gtet_mesh_free(&hooked);
    /* one poll per round and per pass, and on one thread one per 65536 points inserted */
    TEST_CHECK(never.calls >= st.num_rounds + passes, "%d polls for %d rounds, %d passes",
               never.calls, st.num_rounds, passes);
    if (threads == 1)
        TEST_CHECK(never.in_last_round >= (int)(last->points / 65536),
                   "%d polls inside a last round of %llu points", never.in_last_round,
                   (unsigned long long)last->points);
    else
        TEST_CHECK(never.in_last_round >= last->passes - 1, "%d polls inside %d passes",
                   never.in_last_round, last->passes);
    opt.progress = NULL;
    for (int stop = 1; stop <= never.calls; stop++) {
        poll_state p = {0};
        p.stop_at = stop;
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

static void test_cancel_one_thread(void) { cancel_at_every_poll(1); }
static void test_cancel_two_threads(void) { cancel_at_every_poll(2); }

int main(void)
{
    TU_RUN(test_cancel_one_thread);
    TU_RUN(test_cancel_two_threads);
    return tu_finish();
}
