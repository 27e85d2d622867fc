/* test_api_messages.c -- gtet_options.verbosity and message(): one line per phase at
 * verbosity 1 (validate, sort, insert, finalize, and check when asked), one more per BRIO round
 * at 2, none at 0 or without a callback; every line from the calling thread, outside any
 * parallel region; the mesh is the same whatever the verbosity. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "gigatet.h"
#include "testutil.h"

#define MAXLINES 256

typedef struct lines {
    int n;
    char text[MAXLINES][256];
    int off_thread;  /* lines sent from a worker or inside a parallel region */
} lines;

static void collect(void *user, const char *line)
{
    lines *l = user;
    if (omp_in_parallel() || omp_get_thread_num() != 0) l->off_thread++;
    if (l->n < MAXLINES) {
        strncpy(l->text[l->n], line, sizeof l->text[0] - 1);
        l->text[l->n][sizeof l->text[0] - 1] = '\0';
    }
    l->n++;
}

static double *random_points(size_t n, uint64_t seed)
{
    tu_rng r = {seed};
    double *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < 3 * n; i++) p[i] = tu_uniform(&r);
    return p;
}

/* Triangulate with the given verbosity (and callback when `cb`), collect the lines. */
static gtet_mesh *run(const double *xyz, size_t n, int threads, int verbosity, int cb, int check,
                      lines *out)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = threads;
    o.verbosity = verbosity;
    o.check = check;
    if (cb) {
        o.message = collect;
        o.message_user = out;
    }
    gtet_mesh *m = NULL;
    gtet_status s = gtet_triangulate(xyz, n, &o, &m);
    TEST_CHECK(s == GTET_OK, "triangulate: %s", gtet_status_str(s));
    return m;
}

static int starts(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* Verbosity 1: validate, sort, insert, finalize. */
static void check_phase_lines(const lines *l, int threads)
{
    TEST_CHECK(l->n == 4, "%d threads: %d lines, expected 4", threads, l->n);
    const char *phase[4] = {"validate: ", "sort: ", "insert: ", "finalize: "};
    for (int i = 0; i < 4 && i < l->n; i++)
        TEST_CHECK(starts(l->text[i], phase[i]), "line %d is '%s', expected '%s...'", i,
                   l->text[i], phase[i]);
    TEST_CHECK(l->n < 1 || strstr(l->text[0], "30000 points"), "validate line: '%s'", l->text[0]);
}

/* Verbosity 2 with the check: the phases, one line per round between sort and insert, and the
 * check's line last. */
static void check_round_lines(const lines *l, int threads, int num_rounds)
{
    TEST_CHECK(num_rounds > 1, "only %d rounds", num_rounds);
    TEST_CHECK(l->n == 5 + num_rounds, "%d threads: %d lines for %d rounds", threads, l->n,
               num_rounds);
    int rounds = 0;
    for (int i = 0; i < l->n && i < MAXLINES; i++) {
        if (!starts(l->text[i], "round ")) continue;
        int k = 0, of = 0;
        TEST_CHECK(sscanf(l->text[i], "round %d/%d:", &k, &of) == 2 && k == rounds + 1 &&
                       of == num_rounds,
                   "line '%s' (round %d of %d expected)", l->text[i], rounds + 1, num_rounds);
        rounds++;
    }
    TEST_CHECK(rounds == num_rounds, "%d round lines for %d rounds", rounds, num_rounds);
    TEST_CHECK(l->n >= 5 && starts(l->text[1], "sort: ") &&
                   starts(l->text[l->n - 3], "insert: ") && starts(l->text[l->n - 1], "check: ok"),
               "order of the lines: '%s' ... '%s'", l->text[1], l->text[l->n - 1]);
}

static void test_one_line_per_phase_and_per_round_from_the_calling_thread(void)
{
    const size_t n = 30000;
    double *xyz = random_points(n, 7);
    for (int verbosity = 1; verbosity <= 2; verbosity++)
        for (int threads = 1; threads <= 2; threads++) {
            lines l = {0};
            gtet_mesh *m = run(xyz, n, threads, verbosity, 1, verbosity == 2, &l);
            gtet_stats st;
            gtet_mesh_stats(m, &st);
            if (verbosity == 1) check_phase_lines(&l, threads);
            else check_round_lines(&l, threads, st.num_rounds);
            TEST_CHECK(l.off_thread == 0, "%d lines not from the calling thread", l.off_thread);
            gtet_mesh_free(&m);
        }
    free(xyz);
}

static void test_silent_without_verbosity_or_callback_and_same_mesh(void)
{
    const size_t n = 5000;
    double *xyz = random_points(n, 9);
    lines l0 = {0}, l2 = {0};
    /* one thread: the tets come in the same order every run */
    gtet_mesh *a = run(xyz, n, 1, 0, 1, 0, &l0);
    gtet_mesh *b = run(xyz, n, 1, 2, 0, 0, &l2);
    gtet_mesh *c = run(xyz, n, 2, 2, 1, 0, &l2);
    TEST_CHECK(l0.n == 0, "verbosity 0 sent %d lines", l0.n);
    TEST_REQUIRE(a && b && c, "no mesh");
    const size_t nt = gtet_mesh_num_tets(a);
    TEST_CHECK(l2.n > 5, "verbosity 2 with a callback sent %d lines", l2.n);
    TEST_CHECK(nt == gtet_mesh_num_tets(b) && nt == gtet_mesh_num_tets(c), "tet counts differ");
    TEST_CHECK(nt == gtet_mesh_num_tets(b) &&
                   memcmp(gtet_mesh_tets(a), gtet_mesh_tets(b), 4 * nt * sizeof(uint32_t)) == 0,
               "the mesh depends on the verbosity");
    gtet_mesh_free(&a);
    gtet_mesh_free(&b);
    gtet_mesh_free(&c);
    free(xyz);
}

int main(void)
{
    TU_RUN(test_one_line_per_phase_and_per_round_from_the_calling_thread);
    TU_RUN(test_silent_without_verbosity_or_callback_and_same_mesh);
    return tu_finish();
}
