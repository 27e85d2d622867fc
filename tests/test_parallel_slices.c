/* test_parallel_slices.c -- obligation O1 of proofs/parallel.md for the cuts of a parallel pass
 * (src/kernel/slices.c kpar_slices / kpar_colour_of): the slices are consecutive, cover every
 * pending point once, never split equal keys, and the colour a key gets from the ranges is the
 * index of the slice that holds it -- for a round's first pass and for its first retry, whose
 * cuts are rotated half a slice along the looping curve.
 *
 * Specification: for pending keys sorted ascending (pts alongside), after kpar_slices with
 * T threads (rotated or not): the slices [begin[k], end[k]) are consecutive from 0 to np; pts
 * is a permutation of the input and pk[i] is still the key of pts[i]; for every i in slice k,
 * kpar_colour_of(pk[i]) == k; two points with equal keys are in the same slice; with rotate 1
 * the first slice starts half a slice in (within the snap window of the cuts on Moore cells,
 * slice / 64 points either side, or at the first key change past np / (2T) when the cuts are
 * by equal counts); with rotate 2 (a round's first pass) the origin is free.
 * A colour mismatch means a thread inserts a point of another colour: a data race (C4).
 * The cuts on Moore cells (NOTES.md E12): a cluster holding half the keys inside one aligned
 * key range is one slice with two threads, and every cut lies within slice / 64 of the
 * equal-count position of its origin.
 */
#include <stdlib.h>
#include <string.h>

#include "kernel/parallel.h"
#include "testutil.h"

static uint64_t rng(uint64_t *s)
{
    *s += 0x9e3779b97f4a7c15ULL;
    uint64_t z = *s;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* np sorted keys drawn from `distinct` values spread over the 63-bit range (distinct small:
 * long runs of equal keys, some longer than a slice); pts[i] = i. */
static void make_keys(uint64_t *pk, uint32_t *pts, size_t np, uint64_t distinct, uint64_t *seed)
{
    uint64_t *vals = malloc(distinct * sizeof *vals);
    for (uint64_t d = 0; d < distinct; d++) vals[d] = rng(seed) & KPAR_KEY_MASK;
    if (distinct > 1 && rng(seed) % 4 == 0) vals[0] = 0, vals[1] = KPAR_KEY_MASK;  /* both ends */
    for (size_t i = 0; i < np; i++) {
        /* skewed choice: a few values carry most points */
        uint64_t r = rng(seed) % distinct;
        if (rng(seed) % 3 == 0) r = r % (distinct / 4 + 1);
        pk[i] = vals[r];
    }
    qsort(pk, np, sizeof *pk, cmp_u64);
    for (size_t i = 0; i < np; i++) pts[i] = (uint32_t)i;
    free(vals);
}

static int check_case(size_t np, int nth, int rotate, uint64_t distinct, uint64_t seed0)
{
    uint64_t seed = seed0;
    uint64_t *pk = malloc(np * sizeof *pk), *orig = malloc(np * sizeof *orig);
    uint64_t *tk = malloc(np * sizeof *tk);
    uint32_t *pts = malloc(np * sizeof *pts), *ti = malloc(np * sizeof *ti);
    unsigned char *seen = calloc(np, 1);
    make_keys(pk, pts, np, distinct, &seed);
    memcpy(orig, pk, np * sizeof *pk);
    size_t begin[256], end[256];
    uint64_t rel[256], bound0;
    kpar_slices(pk, pts, np, nth, rotate, NULL, tk, ti, begin, end, rel, &bound0);
    int bad = 0;
#define FAIL(...) do { if (!bad) TEST_CHECK(0, __VA_ARGS__); bad = 1; } while (0)
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        if (begin[k] != at || end[k] < begin[k]) FAIL("np %zu T %d rot %d: slice %d is [%zu,%zu), expected to start at %zu",
                                                      np, nth, rotate, k, begin[k], end[k], at);
        at = end[k];
    }
    if (at != np) FAIL("np %zu T %d rot %d: slices end at %zu", np, nth, rotate, at);
    for (size_t i = 0; i < np && !bad; i++) {
        if (pts[i] >= np || seen[pts[i]]) FAIL("pts is not a permutation (index %zu)", i);
        else seen[pts[i]] = 1;
        if (!bad && orig[pts[i]] != pk[i]) FAIL("pk[%zu] is not the key of pts[%zu]", i, i);
    }
    for (int k = 0; k < nth && !bad; k++)
        for (size_t i = begin[k]; i < end[k]; i++) {
            const int c = kpar_colour_of(pk[i], rel, bound0, nth);
            if (c != k) {
                FAIL("np %zu T %d rot %d distinct %llu: point %zu of slice %d has colour %d",
                     np, nth, rotate, (unsigned long long)distinct, i, k, c);
                break;
            }
        }
    /* equal keys in one slice: with every slice's points coloured right (above), two equal keys
     * in different slices would get different colours from one key -- impossible; check the
     * cuts directly as well */
    for (int k = 1; k < nth && !bad; k++)
        if (begin[k] > 0 && begin[k] < np && begin[k] < end[k] && pk[begin[k]] == pk[begin[k] - 1])
            FAIL("np %zu T %d rot %d: the cut before slice %d splits equal keys", np, nth, rotate, k);
    if (rotate == 1 && !bad && np > 0) {
        const size_t s = np / (size_t)nth, tol = s / 64;
        size_t off = np / (2 * (size_t)nth);
        while (off > 0 && off < np && orig[off] == orig[off - 1]) off++;
        /* pts[i] was i: the first slice starts at sorted index pts[0]; equal-count cuts (no
         * gap to snap to, or tol 0) rotate by off, or not at all when off is 0 or np */
        const size_t start = pts[0];
        const int snapped = tol > 0 && start + tol >= s / 2 && start <= s / 2 + tol;
        const int counted = (off > 0 && off < np) ? start == off : start == 0;
        if (!snapped && !counted)
            FAIL("np %zu T %d: the rotated slices start at %zu, not half a slice in", np, nth,
                 start);
    }
#undef FAIL
    free(pk);
    free(orig);
    free(tk);
    free(pts);
    free(ti);
    free(seen);
    return !bad;
}

static void test_every_point_of_a_slice_has_its_colour_with_and_without_rotation(void)
{
    static const size_t sizes[] = {1, 2, 3, 7, 64, 1000, 4097, 30000};
    static const int threads[] = {2, 3, 4, 8, 16, 255};
    static const uint64_t distinct[] = {1, 2, 3, 5, 40, 1000, 1000000};
    uint64_t seed = 1;
    int cases = 0, ok = 0;
    for (size_t a = 0; a < sizeof sizes / sizeof *sizes; a++)
        for (size_t b = 0; b < sizeof threads / sizeof *threads; b++)
            for (size_t d = 0; d < sizeof distinct / sizeof *distinct; d++)
                for (int rot = 0; rot < 3; rot++)
                    for (int rep = 0; rep < 3; rep++) {
                        cases++;
                        ok += check_case(sizes[a], threads[b], rot, distinct[d], seed++);
                    }
    TEST_CHECK(ok == cases, "%d of %d cases failed", cases - ok, cases);
}

/* The rotation moves the cuts: with two threads and distinct keys, the rotated first slice
 * starts at index np/4 of the sorted keys, so the two partitions differ (a retry on the same
 * cuts would meet the same conflicts). */
static void test_the_first_retry_cuts_elsewhere(void)
{
    const size_t np = 1000;
    uint64_t pk[1000], tk[1000], sorted[1000];
    uint32_t pts[1000], ti[1000];
    for (size_t i = 0; i < np; i++) pk[i] = sorted[i] = (uint64_t)i * 1000003u, pts[i] = (uint32_t)i;
    size_t begin[2], end[2];
    uint64_t rel[2], bound0;
    kpar_slices(pk, pts, np, 2, 1, NULL, tk, ti, begin, end, rel, &bound0);
    /* the cuts snap to Moore cells within 500 / 64 = 7 points of the equal counts */
    TEST_CHECK(pts[0] >= 243 && pts[0] <= 257 && pk[0] == sorted[pts[0]],
               "rotated start %llu (point %u), expected point 250 +- 7",
               (unsigned long long)pk[0], pts[0]);
    TEST_CHECK(pts[begin[1]] >= 743 && pts[begin[1]] <= 757,
               "second slice starts at %zu with point %u, expected 750 +- 7", begin[1],
               pts[begin[1]]);
    TEST_CHECK(kpar_colour_of(sorted[0], rel, bound0, 2) == 1 &&
               kpar_colour_of(sorted[300], rel, bound0, 2) == 0 &&
               kpar_colour_of(sorted[800], rel, bound0, 2) == 1,
               "colours of the unrotated halves' points are not the rotated slices'");
}

/* n sorted keys, every other one inside one aligned range of 8^12 keys that starts 3/10 of
 * the way along (a cube of the curve: a dense cluster), the rest spread over the whole range
 * outside it; pts[i] = i. */
#define CLUSTER_LO (UINT64_C(3) << 57 | UINT64_C(5) << 54)
#define CLUSTER_SIDE (UINT64_C(1) << 36)
static int in_cluster(uint64_t k) { return k >= CLUSTER_LO && k < CLUSTER_LO + CLUSTER_SIDE; }

static void cluster_keys(uint64_t *pk, uint32_t *pts, size_t n)
{
    uint64_t seed = 99;
    for (size_t i = 0; i < n; i++) {
        if (i % 2) pk[i] = CLUSTER_LO + rng(&seed) % CLUSTER_SIDE;
        else do pk[i] = rng(&seed) & KPAR_KEY_MASK; while (in_cluster(pk[i]));
    }
    qsort(pk, n, sizeof *pk, cmp_u64);
    for (size_t i = 0; i < n; i++) pts[i] = (uint32_t)i;
}

/* Cuts on Moore cells (kpar_slices, rotate 2: a round's first pass).  40000 keys: 20000
 * spread over the whole range and 20000 inside one aligned range of 8^12 keys (a cube of the
 * curve, a dense cluster), which starts 3/10 of the way along.  With equal counts and origin
 * 0 the cut would fall inside the cluster; the coarsest cuts are the cluster's own ends, so
 * the cluster lies in one slice (a cut may take a coarser cell boundary between spread keys
 * near the cluster's end).  Specification: the cluster's keys all in one slice, each slice
 * within 2 * 20000 / 64 keys of 20000 (every colour right: check_case covers that). */
static void test_a_cluster_in_one_cube_is_one_slice(void)
{
    enum { N = 40000 };
    static uint64_t pk[N], tk[N];
    static uint32_t pts[N], ti[N];
    cluster_keys(pk, pts, N);
    size_t begin[2], end[2];
    uint64_t rel[2], bound0;
    kpar_slices(pk, pts, N, 2, 2, NULL, tk, ti, begin, end, rel, &bound0);
    const size_t tol = N / 2 / 64, n0 = end[0] - begin[0];
    TEST_CHECK(n0 + 2 * tol >= N / 2 && n0 <= N / 2 + 2 * tol, "slices of %zu and %zu keys", n0,
               end[1] - begin[1]);
    int in[2] = {0, 0};
    for (int k = 0; k < 2; k++)
        for (size_t i = begin[k]; i < end[k]; i++) in[k] += in_cluster(pk[i]);
    TEST_CHECK((in[0] == N / 2 && in[1] == 0) || (in[1] == N / 2 && in[0] == 0),
               "the cluster's keys are split %d / %d between the slices", in[0], in[1]);
}

/* The first retry after cuts from a free origin (NOTES.md E20).  The previous pass (two
 * threads) had its colour boundaries at keys B0 = 3/10 and B1 = 7/10 of the range, and the
 * deferred points crowd around them: 3000 keys within d of B0 and 3000 within d of B1.  A
 * retry that cut by counts half a slice from the first key would cut at B0 and B1 again (the
 * old code: every crowd split in two).  Specification: with prev given, each crowd lies in one
 * slice, the two crowds in different ones, and every point of slice k has colour k. */
static void test_the_retry_after_a_free_origin_cuts_between_the_crowds(void)
{
    enum { N = 6000 };
    static uint64_t pk[N], tk[N];
    static uint32_t pts[N], ti[N];
    const uint64_t B0 = KPAR_KEY_MASK / 10 * 3, B1 = KPAR_KEY_MASK / 10 * 7;
    const uint64_t d = UINT64_C(1) << 50;
    uint64_t seed = 7;
    for (size_t i = 0; i < N; i++) pk[i] = (i % 2 ? B1 : B0) - d + rng(&seed) % (2 * d);
    qsort(pk, N, sizeof *pk, cmp_u64);
    for (size_t i = 0; i < N; i++) pts[i] = (uint32_t)i;
    kpar_cuts prev = {.rel = {0, B1 - B0}, .bound0 = B0, .nth = 2};
    size_t begin[2], end[2];
    uint64_t rel[2], bound0;
    kpar_slices(pk, pts, N, 2, 1, &prev, tk, ti, begin, end, rel, &bound0);
    int crowd[2][2] = {{0, 0}, {0, 0}}, wrong = 0;  /* [crowd][slice] */
    for (int k = 0; k < 2; k++)
        for (size_t i = begin[k]; i < end[k]; i++) {
            crowd[pk[i] > (B0 + B1) / 2][k]++;
            wrong += kpar_colour_of(pk[i], rel, bound0, 2) != k;
        }
    TEST_CHECK(wrong == 0, "%d points have another slice's colour", wrong);
    TEST_CHECK((crowd[0][0] == 0 || crowd[0][1] == 0) && (crowd[1][0] == 0 || crowd[1][1] == 0),
               "a crowd around an old boundary is split: %d / %d and %d / %d", crowd[0][0],
               crowd[0][1], crowd[1][0], crowd[1][1]);
    TEST_CHECK(end[0] - begin[0] == N / 2, "slices of %zu and %zu points", end[0] - begin[0],
               end[1] - begin[1]);
}

/* kpar_slices's origin search (a round's first pass, rotate 2) runs on the slices' threads
 * past 65536 keys (slices.c best_origin): its answer must be the one-thread answer.  The same
 * call from inside a one-thread team's nested region (nesting is off: the search's region
 * gets one thread) gives the same slices, ranges and order, on cluster keys (the search is not
 * skipped: origin 0 cuts the cluster) and on keys with long runs of equal values. */
static void test_the_origin_search_gives_the_one_thread_answer(void)
{
    enum { N = 200000 };
    static uint64_t pk[N], pk1[N], tk[N];
    static uint32_t pts[N], pts1[N], ti[N];
    int bad = 0;
    for (int set = 0; set < 4 && !bad; set++)
        for (int nth = 2; nth <= 4 && !bad; nth++) {
            uint64_t seed = 7 + (uint64_t)set;
            const size_t n = N - 1000 * (size_t)set;
            if (set % 2 == 0) cluster_keys(pk, pts, n);
            else make_keys(pk, pts, n, set == 1 ? 1000 : 100000, &seed);
            memcpy(pk1, pk, n * sizeof *pk);
            memcpy(pts1, pts, n * sizeof *pts);
            size_t b[256], e[256], b1[256], e1[256];
            uint64_t rel[256], rel1[256], bound0, bound1;
            kpar_slices(pk, pts, n, nth, 2, NULL, tk, ti, b, e, rel, &bound0);
#pragma omp parallel num_threads(2)
#pragma omp single
            kpar_slices(pk1, pts1, n, nth, 2, NULL, tk, ti, b1, e1, rel1, &bound1);
            int same = bound0 == bound1 && !memcmp(pk, pk1, n * sizeof *pk) &&
                       !memcmp(pts, pts1, n * sizeof *pts);
            for (int k = 0; k < nth; k++) same &= b[k] == b1[k] && e[k] == e1[k] && rel[k] == rel1[k];
            if (!same) {
                TEST_CHECK(0, "set %d, %d threads: slices start at %zu / %zu (one thread %zu / %zu)",
                           set, nth, b[0], b[1], b1[0], b1[1]);
                bad = 1;
            }
        }
}

int main(void)
{
    TU_RUN(test_every_point_of_a_slice_has_its_colour_with_and_without_rotation);
    TU_RUN(test_the_first_retry_cuts_elsewhere);
    TU_RUN(test_a_cluster_in_one_cube_is_one_slice);
    TU_RUN(test_the_retry_after_a_free_origin_cuts_between_the_crowds);
    TU_RUN(test_the_origin_search_gives_the_one_thread_answer);
    return tu_finish();
}
