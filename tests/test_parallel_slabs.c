/* test_parallel_slabs.c -- obligation O1 of proofs/parallel.md for the slabs of a round's retry
 * passes (src/kernel/slabs.c kpar_slabs / kpar_slab_of, NOTES.md E40), and the selection they
 * rest on (kpar_select).
 *
 * Specification: after kpar_slabs with T threads returned 1, the slices [begin[k], end[k]) are
 * consecutive from 0 to np, pts is a permutation of the input that keeps the input order within
 * each slice, every point of slice k has kpar_slab_of(its coordinate on the chosen axis) == k
 * (else a thread would insert a point of another colour: a data race, C4), each slice holds at
 * least np / (2T) points (random coordinates always allow that; 8 distinct values may not), the cuts are the coordinates of ranks np k / T, and the axis is the
 * one whose 1/4 .. 3/4 quantiles lie farthest apart.  When no balanced slabs exist (equal
 * coordinates) it returns 0 and leaves pts as it was.  kpar_select returns the element of the
 * asked rank of the ascending order, for any input order and any duplicates.
 */
#include <stdlib.h>
#include <string.h>

#include "kernel/slabs.h"
#include "testutil.h"

static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* a[i] for pattern p: random, few distinct values, ascending, descending, all equal,
 * organ pipe */
static double pattern(int p, size_t i, size_t n, tu_rng *r)
{
    switch (p) {
    case 0: return tu_uniform(r) - 0.5;
    case 1: return (double)tu_below(r, 5);
    case 2: return (double)i;
    case 3: return (double)(n - i);
    case 4: return 7.0;
    default: return (double)(i < n / 2 ? i : n - i);
    }
}

static void test_select_gives_the_rank_of_the_sorted_order(void)
{
    static const size_t sizes[] = {1, 2, 3, 5, 17, 100, 1001, 20000};
    tu_rng r = {11};
    int bad = 0;
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes && !bad; s++)
        for (int p = 0; p < 6 && !bad; p++) {
            const size_t n = sizes[s];
            double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
            for (size_t i = 0; i < n; i++) a[i] = pattern(p, i, n, &r);
            memcpy(b, a, n * sizeof *a);
            qsort(b, n, sizeof *b, cmp_d);
            for (size_t k = 0; k < 40 && !bad; k++) {
                const size_t rank = k == 0 ? 0 : k == 1 ? n - 1 : (size_t)tu_below(&r, n);
                memcpy(c, a, n * sizeof *a);
                const double x = kpar_select(c, n, rank);
                int split = c[rank] == x;
                for (size_t i = 0; i < n && split; i++)
                    split = i < rank ? c[i] <= x : c[i] >= x;
                if (x != b[rank] || !split) {
                    TEST_CHECK(0, "n %zu pattern %d rank %zu: %g, sorted %g, split %d", n, p, rank,
                               x, b[rank], split);
                    bad = 1;
                }
            }
            free(a);
            free(b);
            free(c);
        }
}

/* np points (ids 0..np) in v: shape 0 uniform in a box stretched by 3 on `wide`; 1 on a sphere
 * with coordinates rounded to 1/8 (many equal coordinates); 2 all on one point. */
static void make_points(double *v, size_t np, int shape, int wide, tu_rng *r)
{
    for (size_t i = 0; i < np; i++)
        for (int d = 0; d < 3; d++) {
            double x = tu_uniform(r) - 0.5;
            if (shape == 0 && d == wide) x *= 3;
            if (shape == 1) x = (double)(long)(x * 8) / 8;
            if (shape == 2) x = 0.25;
            v[3 * i + d] = x;
        }
}

static int check_slabs(size_t np, int nth, int shape, int wide, uint64_t seed)
{
    tu_rng r = {seed};
    double *v = calloc(3 * np, sizeof *v), *scratch = malloc(np * sizeof *scratch);
    double *q = malloc(np * sizeof *q);
    uint32_t *pts = malloc(np * sizeof *pts), *tmp = malloc(np * sizeof *tmp);
    size_t *where = malloc(np * sizeof *where);
    make_points(v, np, shape, wide, &r);
    for (size_t i = 0; i < np; i++) pts[i] = (uint32_t)(np - 1 - i);  /* some input order */
    size_t begin[256], end[256];
    kpar_slab_cuts s;
    int bad = 0;
#define FAIL(...) do { if (!bad) TEST_CHECK(0, __VA_ARGS__); bad = 1; } while (0)
    const int got = kpar_slabs(v, pts, np, nth, scratch, tmp, begin, end, &s);
    if (!got) {
        for (size_t i = 0; i < np; i++)
            if (pts[i] != np - 1 - i) FAIL("np %zu T %d shape %d: refused, but pts changed", np, nth, shape);
        if (shape == 0) FAIL("np %zu T %d shape %d: no slabs", np, nth, shape);
        goto out;
    }
    if (shape == 2) FAIL("np %zu T %d: slabs of equal points", np, nth);
    if (shape == 0 && np >= 1000 && s.axis != wide) FAIL("np %zu T %d: axis %d, the widest is %d", np, nth, s.axis, wide);
    for (size_t i = 0; i < np; i++) q[i] = v[3 * i + s.axis];
    qsort(q, np, sizeof *q, cmp_d);
    for (int k = 1; k < nth; k++)
        if (s.cut[k] != q[np * (size_t)k / (size_t)nth]) FAIL("np %zu T %d: cut %d is not rank n k / T", np, nth, k);
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        if (begin[k] != at || end[k] < begin[k] + np / (2 * (size_t)nth))
            FAIL("np %zu T %d shape %d: slice %d is [%zu,%zu) from %zu", np, nth, shape, k, begin[k], end[k], at);
        at = end[k];
    }
    if (at != np) FAIL("np %zu T %d: slices end at %zu", np, nth, at);
    for (size_t i = 0; i < np; i++) where[i] = np;
    for (size_t i = 0; i < np && !bad; i++) {
        if (pts[i] >= np || where[pts[i]] != np) FAIL("pts is not a permutation (index %zu)", i);
        else where[pts[i]] = i;
    }
    for (int k = 0; k < nth && !bad; k++)
        for (size_t i = begin[k]; i < end[k] && !bad; i++) {
            const double x = v[3 * (size_t)pts[i] + s.axis];
            const int c = kpar_slab_of(x, &s);
            if (c != k) FAIL("np %zu T %d shape %d: point %zu of slice %d has colour %d", np, nth, shape, i, k, c);
            if ((k > 0 && x < s.cut[k]) || (k + 1 < nth && x >= s.cut[k + 1]))
                FAIL("np %zu T %d shape %d: point %zu of slice %d lies outside [cut %d, cut %d)", np, nth, shape, i, k, k, k + 1);
            if (i > begin[k] && pts[i] > pts[i - 1])  /* the input order was descending ids */
                FAIL("np %zu T %d: slice %d does not keep the input order at %zu", np, nth, k, i);
        }
out:
#undef FAIL
    free(v);
    free(scratch);
    free(q);
    free(pts);
    free(tmp);
    free(where);
    return !bad;
}

static void test_slabs_colour_their_points_and_keep_the_order(void)
{
    static const size_t sizes[] = {3, 8, 64, 1000, 30001};
    static const int threads[] = {2, 3, 4, 8, 255};
    int cases = 0, ok = 0;
    uint64_t seed = 1;
    for (size_t a = 0; a < sizeof sizes / sizeof *sizes; a++)
        for (size_t b = 0; b < sizeof threads / sizeof *threads; b++)
            for (int shape = 0; shape < 3; shape++)
                for (int wide = 0; wide < 3; wide++) {
                    if (sizes[a] < 4 * (size_t)threads[b]) continue;  /* too few: refused */
                    cases++;
                    ok += check_slabs(sizes[a], threads[b], shape, wide, seed++);
                }
    TEST_CHECK(ok == cases, "%d of %d cases failed", cases - ok, cases);
}

static void test_too_few_points_or_one_thread_are_refused(void)
{
    double v[3 * 8] = {0};
    for (int i = 0; i < 24; i++) v[i] = i;
    uint32_t pts[8] = {0, 1, 2, 3, 4, 5, 6, 7}, tmp[8];
    double scratch[8];
    size_t begin[256], end[256];
    kpar_slab_cuts s;
    TEST_CHECK(!kpar_slabs(v, pts, 8, 1, scratch, tmp, begin, end, &s), "one thread");
    TEST_CHECK(!kpar_slabs(v, pts, 7, 2, scratch, tmp, begin, end, &s), "7 points, 2 threads");
    TEST_CHECK(kpar_slabs(v, pts, 8, 2, scratch, tmp, begin, end, &s), "8 points, 2 threads");
}

int main(void)
{
    TU_RUN(test_select_gives_the_rank_of_the_sorted_order);
    TU_RUN(test_slabs_colour_their_points_and_keep_the_order);
    TU_RUN(test_too_few_points_or_one_thread_are_refused);
    return tu_finish();
}
