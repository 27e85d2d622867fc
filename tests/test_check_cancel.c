/* test_check_cancel.c -- gtet_check_options.cancel (NOTES.md Q63, E246): the checker polls it
 * on the calling thread only, before each stage and inside the long loops; a nonzero answer at
 * any poll stops the check with GTET_ERR_CANCELLED and a report that says so (stage
 * "cancelled", no verdict), the callback is not called again after it; a callback that never
 * stops gives the same status and report as gtet_check / gtet_check_arrays without it.  The
 * polls inside the loops are what let a cancel land in the orientation, facet, link, Delaunay
 * and full stages: each of those must be the running stage for some poll count.
 */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "gigatet.h"
#include "testutil.h"

#ifdef GTET_TEST_SMALL
#define GTET_TEST_N_CANONICAL 6000
#else
#define GTET_TEST_N_CANONICAL 12000
#endif

typedef struct poll_state {
    int calls;
    int stop_at;       /* answer 1 from this call on (counting from 1); 0: never */
    int foreign;       /* calls made on another thread than the caller's */
    pthread_t caller;
} poll_state;

static int poll_hook(void *user)
{
    poll_state *p = user;
    p->foreign += !pthread_equal(pthread_self(), p->caller);
    p->calls++;
    return p->stop_at && p->calls >= p->stop_at;
}

typedef struct mesh_arrays {
    gtet_mesh *m;
    double *xyz;
    size_t n;
} mesh_arrays;

static mesh_arrays make(size_t n, uint64_t seed)
{
    mesh_arrays a = {NULL, NULL, n};
    tu_rng r = {seed};
    a.xyz = malloc(3 * n * sizeof *a.xyz);
    if (!a.xyz) return a;
    for (size_t i = 0; i < 3 * n; i++) a.xyz[i] = tu_uniform(&r);
    if (gtet_triangulate(a.xyz, n, NULL, &a.m) != GTET_OK) a.m = NULL;
    return a;
}

/* The stage named in a cancelled report's message ("cancelled during the X stage: ..."). */
static void stage_of(const char *msg, char *out, size_t cap)
{
    const char *p = strstr(msg, "during the ");
    out[0] = 0;
    if (!p) return;
    p += strlen("during the ");
    size_t k = 0;
    while (p[k] && p[k] != ' ' && k + 1 < cap) out[k] = p[k], k++;
    out[k] = 0;
}

static int seen(char stages[][32], int ns, const char *s)
{
    for (int i = 0; i < ns; i++)
        if (!strcmp(stages[i], s)) return 1;
    return 0;
}

/* Every poll count up to 12, then ~24 more spread over the whole run: each stops the check. */
static void cancel_everywhere(unsigned flags, size_t n, const char *const *want, int nwant)
{
    mesh_arrays a = make(n, 20261128);
    TEST_REQUIRE(a.m != NULL, "triangulate %zu points", n);
    const double *V = gtet_mesh_vertices(a.m);
    const uint32_t *T = gtet_mesh_tets(a.m), *NB = gtet_mesh_neighbors(a.m);
    const size_t nv = gtet_mesh_num_vertices(a.m), nt = gtet_mesh_num_tets(a.m);
    gtet_check_report ref, ref_arrays, rep;
    const gtet_status s0 = gtet_check(a.m, a.xyz, n, flags, &ref);
    const gtet_status s1 = gtet_check_arrays(V, nv, T, nt, NB, a.xyz, n, flags, &ref_arrays);
    TEST_CHECK(s0 == GTET_OK && s1 == GTET_OK, "plain checks pass: %s / %s", ref.message,
               ref_arrays.message);

    gtet_check_options o;
    gtet_check_options_init(&o);
    TEST_CHECK(o.flags == 0 && o.cancel == NULL && o.cancel_user == NULL, "defaults");
    o.flags = flags;
    poll_state never = {0, 0, 0, pthread_self()};
    o.cancel = poll_hook;
    o.cancel_user = &never;
    gtet_status s = gtet_check_opt(a.m, a.xyz, n, &o, &rep);
    TEST_CHECK(s == s0 && memcmp(&rep, &ref, sizeof rep) == 0,
               "a callback that never stops: same report (%s / %s)", rep.message, ref.message);
    const int calls_mesh = never.calls;
    never.calls = 0;
    s = gtet_check_arrays_opt(V, nv, T, nt, NB, a.xyz, n, &o, &rep);
    TEST_CHECK(s == s1 && memcmp(&rep, &ref_arrays, sizeof rep) == 0,
               "gtet_check_arrays_opt, never stopping: same report (%s)", rep.message);
    TEST_CHECK(never.foreign == 0, "%d polls on another thread than the caller's",
               never.foreign);
    const int total = never.calls;
    /* at least one poll per stage and more inside the loops */
    TEST_CHECK(total > 20 && calls_mesh > 20, "%d / %d polls", total, calls_mesh);

    /* The calling thread's share of a dynamically scheduled loop varies from run to run, and
     * so does the number of polls: a run that polls fewer than k times must give the plain
     * verdict; one that reaches poll k must stop there. */
    char stages[16][32];
    int ns = 0, runs = 0;
    for (int k = 1; k <= total; k = k < 10 ? k + 1 : k + 1 + total / 40, runs++) {
        poll_state p = {0, k, 0, pthread_self()};
        o.cancel_user = &p;
        memset(&rep, 0xA5, sizeof rep);
        s = gtet_check_arrays_opt(V, nv, T, nt, NB, a.xyz, n, &o, &rep);
        TEST_CHECK(p.foreign == 0, "stop at poll %d: %d foreign polls", k, p.foreign);
        if (p.calls < k) {
            TEST_CHECK(s == s1 && memcmp(&rep, &ref_arrays, sizeof rep) == 0,
                       "%d polls, fewer than %d: the plain verdict (%s)", p.calls, k,
                       rep.message);
            continue;
        }
        TEST_CHECK(s == GTET_ERR_CANCELLED, "stop at poll %d of %d: status %d (%s)", k, total,
                   (int)s, rep.message);
        TEST_CHECK(p.calls == k, "stop at poll %d: called %d times", k, p.calls);
        TEST_CHECK(!rep.ok && rep.violation.stage && !strcmp(rep.violation.stage, "cancelled") &&
                       strstr(rep.message, "cancelled during the ") &&
                       rep.violation.tet[0] == GTET_CHECK_NONE && rep.violation.nvertices == 0,
                   "stop at poll %d: report %s", k, rep.message);
        char st[32];
        stage_of(rep.message, st, sizeof st);
        if (!seen(stages, ns, st) && ns < 16) strcpy(stages[ns++], st);
        if (runs % 4) continue;
        /* the mesh object's entry too, at the same poll */
        poll_state q = {0, k, 0, pthread_self()};
        o.cancel_user = &q;
        s = gtet_check_opt(a.m, a.xyz, n, &o, &rep);
        TEST_CHECK(q.calls < k ? s == s0 : s == GTET_ERR_CANCELLED && !rep.ok,
                   "gtet_check_opt, stop at poll %d (%d polls): %d (%s)", k, q.calls, (int)s,
                   rep.message);
    }
    for (int i = 0; i < nwant; i++)
        TEST_CHECK(seen(stages, ns, want[i]), "no poll count stopped the %s stage", want[i]);
    /* a stop at the very last poll (made after the last stage, on the calling thread): still
     * no verdict */
    poll_state last = {0, 0, 0, pthread_self()};
    o.cancel_user = &last;
    gtet_check_arrays_opt(V, nv, T, nt, NB, a.xyz, n, &o, &rep);
    last.stop_at = last.calls;
    last.calls = 0;
    s = gtet_check_arrays_opt(V, nv, T, nt, NB, a.xyz, n, &o, &rep);
    TEST_CHECK(last.calls < last.stop_at || (s == GTET_ERR_CANCELLED && !rep.ok),
               "stop at the last poll: %d", (int)s);
    gtet_mesh_free(&a.m);
    free(a.xyz);
}

static void cancel_canonical(void)
{
    static const char *const want[] = {"vertices", "orientation", "facets", "links", "delaunay"};
    cancel_everywhere(0, GTET_TEST_N_CANONICAL, want, 5);
}

static void cancel_full(void)
{
    static const char *const want[] = {"full"};
    cancel_everywhere(GTET_CHECK_FULL | GTET_CHECK_DELAUNAY, 700, want, 1);
}

/* opts NULL is the defaults (flags 0, no callback). */
static void null_options(void)
{
    mesh_arrays a = make(3000, 5);
    TEST_REQUIRE(a.m != NULL, "triangulate");
    gtet_check_report r0, r1;
    TEST_CHECK(gtet_check(a.m, a.xyz, a.n, 0, &r0) == GTET_OK, "%s", r0.message);
    TEST_CHECK(gtet_check_opt(a.m, a.xyz, a.n, NULL, &r1) == GTET_OK, "%s", r1.message);
    TEST_CHECK(memcmp(&r0, &r1, sizeof r0) == 0, "same report");
    TEST_CHECK(gtet_check_arrays_opt(gtet_mesh_vertices(a.m), gtet_mesh_num_vertices(a.m),
                                     gtet_mesh_tets(a.m), gtet_mesh_num_tets(a.m), NULL, a.xyz,
                                     a.n, NULL, NULL) == GTET_OK,
               "arrays, NULL options and report");
    gtet_mesh_free(&a.m);
    free(a.xyz);
}

int main(void)
{
    TU_RUN(null_options);
    TU_RUN(cancel_canonical);
    TU_RUN(cancel_full);
    return tu_finish();
}
