/* test_parallel_slabs.c -- obligation O1 of proofs/parallel.md for the slabs of a round's retry
 * passes (src/kernel/slabs.c kpar_slabs / kpar_slab_of, NOTES.md E40), and the selection they
 * rest on (kpar_select).
 *
 * Specification: after kpar_slabs with T threads returned 1, the slices [begin[k], end[k]) are
 * consecutive from 0 to np, pts is a permutation of the input that keeps the input order within
 * each slice, every point of slice k has kpar_slab_of(its coordinate on the chosen axis) == k
 * (else a thread would insert a point of another colour: a data race, C4), each slice holds at
 * least np / (2T) points (random coordinates always allow that; 8 distinct values may not),
 * the cuts are the coordinates of ranks np k / T, and the axis is the one where the points
 * crowd least at the cuts (NOTES.md E178): a box stretched on one axis is cut across it, and
 * so is a box stretched more with a sheet of points at that axis's median, which is then cut
 * on another axis; where every axis has equal coordinates at a cut, the widest 1/4 .. 3/4
 * quantile spread wins.  When no balanced slabs exist (equal
 * coordinates) it returns 0 and leaves pts as it was.  kpar_select returns the element of the
 * asked rank of the ascending order, for any input order and any duplicates.
 *
 * A round's first pass (NOTES.md E70): kpar_slab_cuts_on cuts the asked axis even when another
 * is wider; kpar_slabs_at splits at given cuts only when every slab holds np / (2T); kpar_crossing counts, of every stride-th slot, the live finite tets not of one
 * colour under the given colours and under each axis's slabs (dead and ghost slots skipped),
 * as a brute-force count does; kpar_first_axis takes the axis of the fewest crossings only
 * when it is below 3/4 of the colours' count.
 *
 * Run starts (NOTES.md E100): kpar_slab_split lists, per slab, the offsets within its slice of
 * the points that follow a gap of at least min_gap points of other slabs, min_gap the least
 * power of two leaving at most cap of them, as a brute force does.
 */
#include <stdlib.h>
#include <string.h>

#include "kernel/kmesh.h"
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

static void test_cuts_on_a_given_axis_are_its_ranks(void)
{
    enum { N = 5001 };
    tu_rng r = {77};
    double *v = malloc(3 * N * sizeof *v), *scratch = malloc(N * sizeof *scratch);
    double *q = malloc(N * sizeof *q);
    uint32_t *pts = malloc(N * sizeof *pts);
    make_points(v, N, 0, 2, &r);  /* z is the widest; ask for x and y too */
    for (size_t i = 0; i < N; i++) pts[i] = (uint32_t)i;
    for (int axis = -1; axis < 3; axis++) {
        kpar_slab_cuts s;
        TEST_CHECK(kpar_slab_cuts_on(v, pts, N, 3, axis, scratch, &s), "axis %d refused", axis);
        const int want = axis < 0 ? 2 : axis;
        TEST_CHECK(s.axis == want && s.nth == 3, "asked %d, cut %d (%d slabs)", axis, s.axis, s.nth);
        for (size_t i = 0; i < N; i++) q[i] = v[3 * i + want];
        qsort(q, N, sizeof *q, cmp_d);
        for (int k = 1; k < 3; k++)
            TEST_CHECK(s.cut[k] == q[N * (size_t)k / 3], "axis %d: cut %d is not rank N k / 3", axis, k);
        for (size_t i = 0; i < N; i++)
            TEST_CHECK(pts[i] == i, "kpar_slab_cuts_on reordered pts at %zu", i);
    }
    kpar_slab_cuts s;
    for (size_t i = 0; i < N; i++) v[3 * i + 1] = 0.5;  /* y flat: no balanced slabs */
    TEST_CHECK(!kpar_slab_cuts_on(v, pts, N, 2, 1, scratch, &s), "slabs across a flat axis");
    TEST_CHECK(!kpar_slab_cuts_on(v, pts, N, 2, 3, scratch, &s), "axis 3 accepted");
    free(v);
    free(scratch);
    free(q);
    free(pts);
}

/* The retry's axis (E178): x is stretched 6x, so its 1/4 .. 3/4 spread is the widest with or
 * without a sheet of 40% of the points at x = 0 (+- 1e-6), the median; with the sheet the cut
 * on x would run through it (with 3 threads both cuts would: the sheet holds the ranks from
 * 3/10 to 7/10), and the rule takes another axis.  With 7 distinct coordinates on every axis
 * (every window at a cut has width 0) the widest spread decides. */
static void test_the_axis_avoids_a_crowd_at_the_cut(void)
{
    enum { N = 20000 };
    tu_rng r = {123};
    double *v = malloc(3 * N * sizeof *v), *scratch = malloc(N * sizeof *scratch);
    uint32_t *pts = malloc(N * sizeof *pts);
    for (size_t i = 0; i < N; i++) pts[i] = (uint32_t)i;
    for (int sheet = 0; sheet < 2; sheet++) {
        for (size_t i = 0; i < N; i++) {
            v[3 * i] = 6 * (tu_uniform(&r) - 0.5);
            if (sheet && tu_below(&r, 5) < 2) v[3 * i] = 1e-6 * (tu_uniform(&r) - 0.5);
            v[3 * i + 1] = tu_uniform(&r) - 0.5;
            v[3 * i + 2] = tu_uniform(&r) - 0.5;
        }
        for (int nth = 2; nth <= 3; nth++) {
            kpar_slab_cuts s;
            TEST_CHECK(kpar_slab_cuts_on(v, pts, N, nth, -1, scratch, &s), "refused");
            if (sheet) TEST_CHECK(s.axis != 0, "%d threads: cut across the sheet at the median", nth);
            else TEST_CHECK(s.axis == 0, "%d threads: axis %d, not the stretched x", nth, s.axis);
        }
    }
    for (size_t i = 0; i < N; i++)  /* 7 values on each axis, y's 3x apart */
        for (int d = 0; d < 3; d++) v[3 * i + d] = (double)tu_below(&r, 7) * (d == 1 ? 3 : 1);
    kpar_slab_cuts s;
    TEST_CHECK(kpar_slab_cuts_on(v, pts, N, 2, -1, scratch, &s), "7 values refused");
    TEST_CHECK(s.axis == 1, "7 values on every axis: axis %d, not the widest y", s.axis);
    free(v);
    free(scratch);
    free(pts);
}

/* kpar_slabs_at: given cuts split like kpar_slab_split when balanced, else nothing changes. */
static void test_given_cuts_split_only_when_balanced(void)
{
    enum { N = 4000 };
    tu_rng r = {91};
    double *v = malloc(3 * N * sizeof *v);
    uint32_t *pts = malloc(N * sizeof *pts), *tmp = malloc(N * sizeof *tmp);
    make_points(v, N, 0, 1, &r);
    for (size_t i = 0; i < N; i++) pts[i] = (uint32_t)(N - 1 - i);
    size_t begin[256], end[256];
    kpar_slab_cuts s = {.axis = 1, .nth = 2};
    s.cut[1] = 1.4;  /* y in [-1.5, 1.5): about 1/30 of the points above */
    TEST_CHECK(!kpar_slabs_at(v, pts, N, &s, tmp, begin, end, NULL), "unbalanced cuts accepted");
    for (size_t i = 0; i < N; i++)
        TEST_CHECK(pts[i] == N - 1 - i, "refused, but pts changed at %zu", i);
    s.cut[1] = 0.1;
    TEST_CHECK(kpar_slabs_at(v, pts, N, &s, tmp, begin, end, NULL), "balanced cuts refused");
    TEST_CHECK(begin[0] == 0 && end[0] == begin[1] && end[1] == N, "slices [%zu,%zu) [%zu,%zu)",
               begin[0], end[0], begin[1], end[1]);
    for (int k = 0; k < 2; k++)
        for (size_t i = begin[k]; i < end[k]; i++) {
            TEST_CHECK(kpar_slab_of(v[3 * (size_t)pts[i] + 1], &s) == k, "point %zu not in slab %d", i, k);
            TEST_CHECK(i == begin[k] || pts[i] < pts[i - 1], "slab %d lost the order at %zu", k, i);
        }
    free(v);
    free(pts);
    free(tmp);
}

static void test_crossing_counts_match_a_brute_force_count(void)
{
    enum { NV = 400, NT = 3000 };
    tu_rng r = {5};
    double v[3 * NV];
    uint8_t col[NV];
    uint32_t tv[4 * NT];
    for (size_t i = 0; i < NV; i++) {
        for (int d = 0; d < 3; d++) v[3 * i + d] = tu_uniform(&r);
        col[i] = (uint8_t)(v[3 * i] + v[3 * i + 1] > 1.0);  /* a diagonal plane */
    }
    for (size_t t = 0; t < NT; t++) {
        /* vertices near each other (short tets) or anywhere (long ones) */
        const uint32_t a = (uint32_t)tu_below(&r, NV);
        for (int i = 0; i < 4; i++)
            tv[4 * t + i] = t % 3 ? (uint32_t)tu_below(&r, NV) : (a + (uint32_t)i) % NV;
        if (t % 7 == 0) tv[4 * t + 3] = KM_GHOST;
        if (t % 11 == 0) tv[4 * t] |= KM_DEAD;
    }
    kpar_slab_cuts s[3];
    for (int d = 0; d < 3; d++) {
        s[d] = (kpar_slab_cuts){.axis = d, .nth = 3};
        s[d].cut[1] = 0.3 + 0.1 * d;
        s[d].cut[2] = 0.6 + 0.1 * d;
    }
    for (size_t stride = 1; stride <= 8; stride += 7) {
        size_t want[4] = {0, 0, 0, 0}, got[4];
        for (size_t t = 0; t < NT; t += stride) {
            const uint32_t *q = tv + 4 * t;
            if ((q[0] & KM_DEAD) || q[3] == KM_GHOST) continue;
            int mixed = 0;
            for (int i = 1; i < 4; i++) mixed |= col[q[i]] != col[q[0]];
            want[0] += (size_t)mixed;
            for (int d = 0; d < 3; d++) {
                int lo = 3, hi = -1;
                for (int i = 0; i < 4; i++) {
                    const double x = v[3 * (size_t)q[i] + d];
                    const int k = x < s[d].cut[1] ? 0 : x < s[d].cut[2] ? 1 : 2;
                    lo = k < lo ? k : lo;
                    hi = k > hi ? k : hi;
                }
                want[1 + d] += (size_t)(lo != hi);
            }
        }
        kpar_crossing(tv, NT, stride, v, col, s, 2, got);
        for (int k = 0; k < 4; k++)
            TEST_CHECK(got[k] == want[k] && want[k] > 0, "stride %zu: count %d is %zu, brute force %zu",
                       stride, k, got[k], want[k]);
    }
}

static void test_the_first_pass_takes_slabs_only_for_a_clear_gain(void)
{
    const size_t keep[][4] = {{100, 100, 100, 100}, {100, 80, 90, 76}, {0, 0, 0, 0},
                              {100, 75, 75, 75}};
    for (size_t i = 0; i < sizeof keep / sizeof *keep; i++)
        TEST_CHECK(kpar_first_axis(keep[i]) == -1, "case %zu: took axis %d", i,
                   kpar_first_axis(keep[i]));
    const size_t take[][4] = {{100, 74, 90, 80}, {27094, 281, 326, 27097}, {18117, 17395, 10212, 15389},
                              {100, 50, 50, 60}, {100, 60, 60, 50}};
    const int axis[] = {0, 0, 1, 0, 2};
    for (size_t i = 0; i < sizeof take / sizeof *take; i++)
        TEST_CHECK(kpar_first_axis(take[i]) == axis[i], "case %zu: axis %d, want %d", i,
                   kpar_first_axis(take[i]), axis[i]);
}

/* kpar_slab_split's run starts (NOTES.md E100) against a brute force: for every slab, the offsets (within its
 * slice) of the points whose slab's previous point lies gap >= min_gap points before them, and
 * min_gap the least power of two that leaves at most cap of them. */
static void check_runs(const double *v, const uint32_t *pts, size_t np, const kpar_slab_cuts *s,
                       size_t cap, const char *what)
{
    uint32_t *at = malloc((size_t)s->nth * cap * sizeof *at);
    uint32_t *q = malloc(np * sizeof *q), *tmp = malloc(np * sizeof *tmp);
    memcpy(q, pts, np * sizeof *q);
    kpar_runs r = {.at = at, .cap = cap};
    size_t begin[256], end[256];
    kpar_slab_split(v, q, np, s, tmp, begin, end, &r);
    for (int k = 0; k < s->nth; k++) {
        size_t want_gap = 1;
        for (;; want_gap *= 2) {  /* the least power of two leaving <= cap runs */
            size_t n = 0, last = SIZE_MAX;
            for (size_t i = 0; i < np; i++) {
                if (kpar_slab_of(v[3 * (size_t)pts[i] + s->axis], s) != k) continue;
                n += last != SIZE_MAX && i - last - 1 >= want_gap;
                last = i;
            }
            if (n <= cap) break;
        }
        TEST_CHECK(r.min_gap[k] == want_gap, "%s: slab %d min_gap %zu, want %zu", what, k,
                   r.min_gap[k], want_gap);
        size_t n = 0, last = SIZE_MAX, off = 0;
        for (size_t i = 0; i < np; i++) {
            if (kpar_slab_of(v[3 * (size_t)pts[i] + s->axis], s) != k) continue;
            if (last != SIZE_MAX && i - last - 1 >= want_gap) {
                TEST_CHECK(n < r.n[k] && at[(size_t)k * cap + n] == off,
                           "%s: slab %d run %zu at %zu, listed %u", what, k, n, off,
                           n < r.n[k] ? at[(size_t)k * cap + n] : 0u);
                n++;
            }
            last = i;
            off++;
        }
        TEST_CHECK(r.n[k] == n, "%s: slab %d has %zu runs listed, brute force %zu", what, k,
                   r.n[k], n);
        TEST_CHECK(end[k] - begin[k] == off, "%s: slice %d holds %zu points, slab %zu", what,
                   k, end[k] - begin[k], off);
    }
    free(at);
    free(q);
    free(tmp);
}

static void test_runs_are_the_points_after_a_gap(void)
{
    enum { N = 6000 };
    tu_rng r = {17};
    double *v = malloc(3 * N * sizeof *v);
    uint32_t *pts = malloc(N * sizeof *pts);
    for (size_t i = 0; i < N; i++) {
        /* x along a path that crosses the cuts back and forth with runs of every length */
        v[3 * i] = ((i / (1 + i % 37)) % 3) + 0.5 * tu_uniform(&r);
        v[3 * i + 1] = tu_uniform(&r);
        v[3 * i + 2] = tu_uniform(&r);
        pts[i] = (uint32_t)((i * 7919) % N);
    }
    kpar_slab_cuts s = {.axis = 0, .nth = 3};
    s.cut[1] = 1.0;
    s.cut[2] = 2.0;
    check_runs(v, pts, N, &s, 4096, "3 slabs, all runs");
    check_runs(v, pts, N, &s, 40, "3 slabs, cap 40");
    check_runs(v, pts, N, &s, 1, "3 slabs, cap 1");
    s.nth = 2;
    check_runs(v, pts, N, &s, 100, "2 slabs, cap 100");
    /* one slab's points in one run: nothing to list */
    for (size_t i = 0; i < N; i++) pts[i] = (uint32_t)i;
    for (size_t i = 0; i < N; i++) v[3 * i] = i < N / 2 ? 0.5 : 1.5;
    uint32_t at[2 * 8], *tmp = malloc(N * sizeof *tmp);
    size_t begin[256], end[256];
    kpar_runs rr = {.at = at, .cap = 8};
    kpar_slab_split(v, pts, N, &s, tmp, begin, end, &rr);
    free(tmp);
    TEST_CHECK(rr.n[0] == 0 && rr.n[1] == 0, "two runs, one a slab: listed %zu, %zu", rr.n[0],
               rr.n[1]);
    free(v);
    free(pts);
}

int main(void)
{
    TU_RUN(test_select_gives_the_rank_of_the_sorted_order);
    TU_RUN(test_slabs_colour_their_points_and_keep_the_order);
    TU_RUN(test_too_few_points_or_one_thread_are_refused);
    TU_RUN(test_cuts_on_a_given_axis_are_its_ranks);
    TU_RUN(test_the_axis_avoids_a_crowd_at_the_cut);
    TU_RUN(test_given_cuts_split_only_when_balanced);
    TU_RUN(test_crossing_counts_match_a_brute_force_count);
    TU_RUN(test_the_first_pass_takes_slabs_only_for_a_clear_gain);
    TU_RUN(test_runs_are_the_points_after_a_gap);
    return tu_finish();
}
