/* test_kernel_filter_order.c -- the insphere filter's two orders in the kernel
 * (src/kernel/conflict.h km_filter_order, src/pred/filter_packed.h pred_insphere_filter_packed_sf).
 *
 * Specification: the order (static test first, semi-static bound first, or the sampler's
 * choice every KM_ORDER_PERIOD insertions) never changes the mesh, nor do the instances of
 * km_insert that run (AVX2's four-lane filter and the walk's four facet lanes, kernel/
 * insert_avx2.c and walk.h, where the CPU has it, or x86-64's baseline, whose walk tests one
 * facet at a time; the lattice points' coplanar tuples take the walk's exact rest in both):
 * the same points inserted in the same order give the same tet and
 * neighbour arrays, byte for byte.  The sampler picks the second order (with AVX2 the level
 * filter first, NOTES.md E188; else the semi-static bound first, E169) where the static test
 * leaves more than a third of the calls (a cluster whose tets straddle the static bound's
 * scale, and a tiny cluster in a large box, which the static bound never decides: E188 ended
 * E172's exception for it) and keeps the static test first where it leaves nearly none
 * (uniform points).  A sampler that never counted a miss, compared the share the wrong way or
 * kept E172's upper end fails the second test; a semi-static-first bound below the filter's
 * true error (2^-40 times it) answers wrong signs on the points rounded onto a sphere and
 * fails the first (the level filter's bound is tested in test_pred_packed_filter_avx2).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/conflict.h"
#include "testutil.h"

/* points a set: the arrays test's (smaller in sanitized builds); the sampler's shares depend
 * on the spacing, so its sets have 30000 points in every build */
#ifdef GTET_TEST_SMALL
#define N_ARRAYS 6000
#else
#define N_ARRAYS 30000
#endif
#define N_SAMPLER 30000
static int N;

/* 8 corners of [-1, 1]^3, then `cluster` points on a bumpy sphere of radius `radius` around
 * the origin (the rest uniform in the cube), in random order after the corners.  With
 * `degenerate` half of the cluster is rounded onto that sphere (nearly
 * co-spherical tuples: det~ is mostly rounding error, and a bound below the true error
 * answers wrong signs) and half is distinct multiples of 2^-12 in the shell 0.009..0.011
 * (exactly co-spherical and coplanar tuples: calls neither bound decides). */
#define LR 45   /* the lattice shell's outer radius in units of 2^-12 */
static double *points(int cluster, int degenerate, double radius, uint64_t seed)
{
    tu_rng r = {seed};
    double *p = malloc(3 * (size_t)N * sizeof *p);
    unsigned char *used = calloc((size_t)(2 * LR + 1) * (2 * LR + 1) * (2 * LR + 1), 1);
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 3; j++) p[3 * i + j] = (i >> j) & 1 ? 1.0 : -1.0;
    for (int i = 8; i < N; i++) {
        double *q = p + 3 * i;
        if (i - 8 < cluster && degenerate && (i & 1)) {
            int x, y, z, r2;
            size_t at;
            do {
                x = (int)tu_below(&r, 2 * LR + 1) - LR;
                y = (int)tu_below(&r, 2 * LR + 1) - LR;
                z = (int)tu_below(&r, 2 * LR + 1) - LR;
                r2 = x * x + y * y + z * z;
                at = ((size_t)(x + LR) * (2 * LR + 1) + (size_t)(y + LR)) * (2 * LR + 1) +
                     (size_t)(z + LR);
            } while (r2 < 37 * 37 || r2 > LR * LR || used[at]);
            used[at] = 1;
            q[0] = ldexp(x, -12);
            q[1] = ldexp(y, -12);
            q[2] = ldexp(z, -12);
        } else if (i - 8 < cluster) {
            double n2;
            do {
                for (int j = 0; j < 3; j++) q[j] = 2 * tu_uniform(&r) - 1;
                n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
            } while (n2 < 0.01 || n2 > 1);
            const double s =
                radius * (degenerate ? 1.0 : 0.9 + 0.2 * tu_uniform(&r)) / sqrt(n2);
            for (int j = 0; j < 3; j++) q[j] *= s;
        } else {
            for (int j = 0; j < 3; j++) q[j] = 2 * tu_uniform(&r) - 1;
        }
    }
    free(used);
    return p;
}

enum order { STATIC_FIRST, LOCAL_FIRST, SAMPLED, SAMPLED_BASELINE };

typedef struct run {
    size_t nt;
    uint32_t *tv, *tn;
    long local_first_insertions;
    uint64_t walk_steps, orient_calls, orient_exact;  /* the walk's counters */
} run;

/* insert 0..N-1 serially in index order with the order given (SAMPLED_BASELINE: sampled,
 * in km_insert's instances for x86-64's baseline even where the CPU has AVX2); the arrays
 * copied out */
static int build(const double *p, enum order o, run *out)
{
    kmesh m;
    kctx c;
    if (km_init(&m, p, N, 8 * (size_t)N, 1, 0) != GTET_OK) return 0;
    kctx_init(&c, &m, 7);
    if (o == SAMPLED_BASELINE) c.avx2 = 0;
    if (o < SAMPLED) {  /* the sampler never runs: the order stays as set */
        c.order_left = UINT32_MAX;
        c.local_first = o == LOCAL_FIRST;
    }
    int ok = km_first_tet(&c, 0, 1, 2, 4) == GTET_OK;
    out->local_first_insertions = 0;
    for (uint32_t i = 3; ok && i < (uint32_t)N; i++) {
        if (i == 4) continue;
        int deferred = 0;
        ok = km_insert(&c, i, &deferred) == GTET_OK && !deferred;
        out->local_first_insertions += c.local_first;  /* the order this insertion ran with */
    }
    out->walk_steps = c.walk_steps;
    out->orient_calls = c.cnt.orient_calls;
    out->orient_exact = c.cnt.orient_exact;
    out->nt = m.nt;
    out->tv = malloc(m.nt * 4 * sizeof *out->tv);
    out->tn = malloc(m.nt * 4 * sizeof *out->tn);
    memcpy(out->tv, m.tv, m.nt * 4 * sizeof *out->tv);
    memcpy(out->tn, m.tn, m.nt * 4 * sizeof *out->tn);
    kctx_free(&c);
    km_free(&m);
    return ok;
}

static void release(run *r)
{
    free(r->tv);
    free(r->tn);
}

static void test_every_order_builds_the_same_arrays(void)
{
    N = N_ARRAYS;
    for (int k = 0; k < 2; k++) {
        const int cluster = k == 0 ? N - 8 : (N - 8) / 2;
        double *p = points(cluster, k, 0.01, 11 + (uint64_t)k);
        run r[4];
        for (int o = 0; o < 4; o++)
            TEST_REQUIRE(build(p, (enum order)o, &r[o]), "cluster %d: order %d failed", cluster, o);
        for (int o = 1; o < 4; o++)
            TEST_CHECK(r[o].nt == r[0].nt &&
                           memcmp(r[o].tv, r[0].tv, r[0].nt * 4 * sizeof *r[0].tv) == 0 &&
                           memcmp(r[o].tn, r[0].tn, r[0].nt * 4 * sizeof *r[0].tn) == 0,
                       "cluster %d: order %d built other arrays (%zu slots against %zu)",
                       cluster, o, r[o].nt, r[0].nt);
        TEST_CHECK(r[1].local_first_insertions == N - 4, "forced local-first ran %ld of %d",
                   r[1].local_first_insertions, N - 4);
        /* the walks too: the same steps and tests in either instance, and on the lattice
         * points some of the four-lane walk's facets go to the exact rest */
        TEST_CHECK(r[2].walk_steps == r[3].walk_steps && r[2].orient_calls == r[3].orient_calls &&
                       r[2].orient_exact == r[3].orient_exact,
                   "cluster %d: walks differ: steps %llu / %llu, orient3d %llu / %llu, exact "
                   "%llu / %llu", cluster, (unsigned long long)r[2].walk_steps,
                   (unsigned long long)r[3].walk_steps, (unsigned long long)r[2].orient_calls,
                   (unsigned long long)r[3].orient_calls, (unsigned long long)r[2].orient_exact,
                   (unsigned long long)r[3].orient_exact);
        TEST_CHECK(k == 0 || r[2].orient_exact > 0, "no walk test reached the exact stage");
        for (int o = 0; o < 4; o++) release(&r[o]);
        free(p);
    }
}

static void test_the_sampler_follows_the_static_bound(void)
{
#ifndef PRED_INSPHERE_PACKED
    printf("no packed filter on this target: one order only, nothing to sample\n");
    return;
#endif
    N = N_SAMPLER;
    /* the share of calls the static test leaves (a static-first run's count, probed when
     * this test was written): cluster of radius 0.1 ~0.6, of radius 0.01 ~0.98, uniform ~0 */
    double *mid = points(N - 8, 0, 0.1, 21), *tiny = points(N - 8, 0, 0.01, 23);
    double *spread = points(0, 0, 0.01, 22);
    run a, t, b;
    TEST_REQUIRE(build(mid, SAMPLED, &a), "mid cluster run");
    TEST_REQUIRE(build(tiny, SAMPLED, &t), "tiny cluster run");
    TEST_REQUIRE(build(spread, SAMPLED, &b), "uniform run");
    /* the middle share runs the second order most of the time (a sample's share varies
     * along the curve: ~64 % of the insertions when this was written), nearly all misses
     * too but in the first periods, while the mesh is coarse, and nearly none never */
    TEST_CHECK(a.local_first_insertions > (N - 4) / 2,
               "a cluster whose tets straddle the static bound's scale ran the second order "
               "for %ld of %d insertions", a.local_first_insertions, N - 4);
    TEST_CHECK(t.local_first_insertions > (N - 4) / 2,
               "a cluster the static bound never decides ran the second order for %ld of %d "
               "insertions", t.local_first_insertions, N - 4);
    TEST_CHECK(b.local_first_insertions == 0,
               "uniform points ran the second order for %ld insertions", b.local_first_insertions);
    release(&a);
    release(&t);
    release(&b);
    free(mid);
    free(tiny);
    free(spread);
}

int main(void)
{
    TU_RUN(test_every_order_builds_the_same_arrays);
    TU_RUN(test_the_sampler_follows_the_static_bound);
    return tu_finish();
}
