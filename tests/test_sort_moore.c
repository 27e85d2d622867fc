/* test_sort_moore.c -- the Moore-curve keys are a face-adjacent looping bijection with the
 * prefix property, at every depth, on any box, for any thread count.
 *
 * The properties are checked on the keys the library computes, not on its tables: full grids
 * of 2^k cells per axis (k <= 6) for bijection, adjacency and the loop; random cells at every
 * depth up to 21 bits for the local form of adjacency (the cells with keys K-1 and K+1 are
 * face neighbours of the cell with key K); random points on ordinary and extreme boxes for
 * the prefix property and clamping.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sort/sort.h"
#include "testutil.h"

static int adjacent(const double *a, const double *b)
{
    double d = fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]);
    return d == 1.0;
}

/* cell centres of a 2^k grid on the box [0, 2^k]^3 */
static double *grid_points(int k, size_t *n)
{
    const size_t s = (size_t)1 << k, m = s * s * s;
    double *p = malloc(3 * m * sizeof *p);
    size_t i = 0;
    for (size_t z = 0; z < s; z++)
        for (size_t y = 0; y < s; y++)
            for (size_t x = 0; x < s; x++, i++) {
                p[3 * i] = (double)x + 0.5;
                p[3 * i + 1] = (double)y + 0.5;
                p[3 * i + 2] = (double)z + 0.5;
            }
    *n = m;
    return p;
}

static void test_moore_keys_on_full_grids_are_a_face_adjacent_loop(void)
{
    for (int k = 1; k <= 6; k++) {
        size_t n;
        double *p = grid_points(k, &n);
        const double s = ldexp(1.0, k), box[6] = {0, 0, 0, s, s, s};
        uint64_t *key = malloc(n * sizeof *key);
        size_t *cell_of = malloc(n * sizeof *cell_of);
        TEST_REQUIRE(p && key && cell_of, "out of memory");
        sort_moore_keys(p, 3, n, box, k, key, 2);
        for (size_t i = 0; i < n; i++)
            cell_of[i] = SIZE_MAX;
        int bad = 0;
        for (size_t i = 0; i < n && !bad; i++) {
            if (key[i] >= n || cell_of[key[i]] != SIZE_MAX) {
                TEST_CHECK(0, "k=%d: key %llu of cell %zu out of range or repeated", k,
                           (unsigned long long)key[i], i);
                bad = 1;
            } else {
                cell_of[key[i]] = i;
            }
        }
        for (size_t j = 0; j + 1 < n && !bad; j++) {
            if (!adjacent(p + 3 * cell_of[j], p + 3 * cell_of[j + 1])) {
                TEST_CHECK(0, "k=%d: keys %zu and %zu are not face-adjacent cells", k, j, j + 1);
                bad = 1;
            }
        }
        if (!bad)
            TEST_CHECK(adjacent(p + 3 * cell_of[n - 1], p + 3 * cell_of[0]),
                       "k=%d: the curve does not loop (last cell not next to the first)", k);
        free(p);
        free(key);
        free(cell_of);
    }
}

static void test_moore_key_neighbours_are_face_adjacent_at_every_depth(void)
{
    tu_rng rng = {11};
    enum { SAMPLES = 300 };
    double *p = malloc(7 * 3 * SAMPLES * sizeof *p);
    uint64_t *key = malloc(7 * SAMPLES * sizeof *key);
    TEST_REQUIRE(p && key, "out of memory");
    static const int dir[7][3] = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int b = 1; b <= 21; b++) {
        const uint64_t side = (uint64_t)1 << b, total = (uint64_t)1 << (3 * b);
        const double box[6] = {0, 0, 0, (double)side, (double)side, (double)side};
        for (int s = 0; s < SAMPLES; s++) {
            uint64_t c[3] = {tu_below(&rng, side), tu_below(&rng, side), tu_below(&rng, side)};
            for (int d = 0; d < 7; d++)
                for (int a = 0; a < 3; a++)
                    p[3 * (7 * s + d) + a] = (double)c[a] + dir[d][a] + 0.5;
        }
        sort_moore_keys(p, 3, 7 * SAMPLES, box, b, key, 1);
        int bad = 0;
        for (int s = 0; s < SAMPLES && !bad; s++) {
            const uint64_t k0 = key[7 * s], next = (k0 + 1) % total,
                           prev = (k0 + total - 1) % total;
            int seen_next = 0, seen_prev = 0;
            for (int d = 1; d < 7; d++) {
                const double *q = p + 3 * (7 * s + d);
                if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] > (double)side ||
                    q[1] > (double)side || q[2] > (double)side)
                    continue;  /* outside the grid: clamped, not a neighbour */
                seen_next += key[7 * s + d] == next;
                seen_prev += key[7 * s + d] == prev;
            }
            if (seen_next != 1 || seen_prev != 1) {
                TEST_CHECK(0, "bits=%d: key %llu: K+1 seen %d times, K-1 %d times among the "
                           "6 face neighbours", b, (unsigned long long)k0, seen_next, seen_prev);
                bad = 1;
            }
        }
    }
    free(p);
    free(key);
}

static void random_point(tu_rng *rng, const double box[6], double p[3])
{
    for (int a = 0; a < 3; a++) {
        double lo = box[a], hi = box[a + 3];
        double u = tu_uniform(rng) * 1.2 - 0.1;  /* some points outside the box */
        p[a] = lo + u * (hi - lo);
        if (!isfinite(p[a]))
            p[a] = u < 0.5 ? lo : hi;
    }
}

static void test_moore_key_is_monotone_under_refinement(void)
{
    const double boxes[][6] = {
        {0, 0, 0, 1, 1, 1},
        {-3.5, 2.0, 1e6, 7.25, 2.5, 1e6 + 3},
        {-1e308, -1e308, -1e308, 1e308, 1e308, 1e308},  /* hi - lo overflows */
        {1e-310, 2e-310, -5e-309, 4e-310, 3e-310, 5e-309}, /* subnormal extents */
        {0, 0, 5, 1, 1, 5},                               /* a flat axis */
    };
    tu_rng rng = {12};
    enum { N = 2000 };
    double *p = malloc(3 * N * sizeof *p);
    uint64_t *k0 = malloc(N * sizeof *k0), *k1 = malloc(N * sizeof *k1);
    TEST_REQUIRE(p && k0 && k1, "out of memory");
    for (size_t bi = 0; bi < sizeof boxes / sizeof boxes[0]; bi++) {
        for (int i = 0; i < N; i++)
            random_point(&rng, boxes[bi], p + 3 * i);
        sort_moore_keys(p, 3, N, boxes[bi], 1, k0, 1);
        for (int b = 1; b < 21; b++) {
            sort_moore_keys(p, 3, N, boxes[bi], b + 1, k1, 1);
            int bad = 0;
            for (int i = 0; i < N && !bad; i++) {
                if (k1[i] >> 3 != k0[i] || k1[i] >> (3 * (b + 1)) != 0) {
                    TEST_CHECK(0, "box %zu, bits %d->%d, point %d: key %llu is not a prefix of "
                               "%llu", bi, b, b + 1, i, (unsigned long long)k0[i],
                               (unsigned long long)k1[i]);
                    bad = 1;
                }
            }
            memcpy(k0, k1, N * sizeof *k0);
        }
    }
    free(p);
    free(k0);
    free(k1);
}

static void test_moore_keys_clamp_points_outside_the_box(void)
{
    const double box[6] = {-1, -2, -3, 1, 2, 3};
    const double far[][3] = {{-100, 0, 0}, {100, 1.5, -2}, {0.3, -DBL_MAX, DBL_MAX},
                             {1, 2, 3},    {-1, -2, -3},   {5, 5, 5}};
    for (size_t i = 0; i < sizeof far / sizeof far[0]; i++) {
        double c[3];
        for (int a = 0; a < 3; a++)
            c[a] = fmin(fmax(far[i][a], box[a]), box[a + 3]);
        for (int b = 1; b <= 21; b += 5) {
            uint64_t kf, kc;
            sort_moore_keys(far[i], 3, 1, box, b, &kf, 1);
            sort_moore_keys(c, 3, 1, box, b, &kc, 1);
            TEST_CHECK(kf == kc, "point %zu, bits %d: key %llu, clamped point %llu", i, b,
                       (unsigned long long)kf, (unsigned long long)kc);
        }
    }
    /* the corner (xmax,ymax,zmax) is in the last cell of every axis, not past it */
    double top[3] = {1, 2, 3}, below[3] = {1 - 1e-9, 2 - 1e-9, 3 - 1e-9};
    uint64_t kt, kb;
    sort_moore_keys(top, 3, 1, box, 21, &kt, 1);
    sort_moore_keys(below, 3, 1, box, 21, &kb, 1);
    TEST_CHECK(kt == kb, "box corner key %llu differs from the key just inside %llu",
               (unsigned long long)kt, (unsigned long long)kb);
}

static void test_moore_table_walk_equals_level_by_level_walk(void)
{
    /* a batch of >= 1024 points goes through the 9-bit tables, single points through the
     * 3-bit walk: both must give the same keys for every bits, padding included */
    tu_rng rng = {13};
    enum { N = 3000 };
    const double box[6] = {0, 0, 0, 1, 1, 1};
    double *p = malloc(4 * N * sizeof *p);
    uint64_t *k = malloc(N * sizeof *k);
    TEST_REQUIRE(p && k, "out of memory");
    for (int i = 0; i < 4 * N; i++)
        p[i] = tu_uniform(&rng);
    for (int b = 1; b <= 21; b++) {
        sort_moore_keys(p, 4, N, box, b, k, 1);
        int bad = 0;
        for (int i = 0; i < N && !bad; i++) {
            uint64_t one;
            sort_moore_keys(p + 4 * i, 4, 1, box, b, &one, 1);
            if (one != k[i]) {
                TEST_CHECK(0, "bits %d point %d: batch %llu, single %llu", b, i,
                           (unsigned long long)k[i], (unsigned long long)one);
                bad = 1;
            }
        }
    }
    /* the id-gathered variant agrees */
    uint32_t ids[5] = {7, 0, 2999, 7, 1234};
    uint64_t kid[5];
    sort_moore_keys(p, 4, N, box, 21, k, 1);
    sort_moore_keys_ids(p, 4, ids, 5, box, 21, kid, 1);
    for (int i = 0; i < 5; i++)
        TEST_CHECK(kid[i] == k[ids[i]], "sort_moore_keys_ids differs at %d", i);
    free(p);
    free(k);
}

static void test_moore_keys_do_not_depend_on_thread_count(void)
{
    tu_rng rng = {14};
    enum { N = 100000 };
    double *p = malloc(3 * N * sizeof *p);
    uint64_t *ref = malloc(N * sizeof *ref), *k = malloc(N * sizeof *k);
    TEST_REQUIRE(p && ref && k, "out of memory");
    for (int i = 0; i < 3 * N; i++)
        p[i] = tu_uniform(&rng) * 10 - 5;
    const double box[6] = {-5, -5, -5, 5, 5, 5};
    sort_moore_keys(p, 3, N, box, 21, ref, 1);
    for (int t = 2; t <= 4; t++) {
        sort_moore_keys(p, 3, N, box, 21, k, t);
        TEST_CHECK(memcmp(ref, k, N * sizeof *k) == 0, "keys differ with %d threads", t);
    }
    /* bits beyond 21 are taken as 21, bits <= 0 give zeros */
    sort_moore_keys(p, 3, N, box, 40, k, 2);
    TEST_CHECK(memcmp(ref, k, N * sizeof *k) == 0, "bits=40 is not bits=21");
    sort_moore_keys(p, 3, 10, box, 0, k, 1);
    for (int i = 0; i < 10; i++)
        TEST_CHECK(k[i] == 0, "bits=0 gives key %llu", (unsigned long long)k[i]);
    free(p);
    free(ref);
    free(k);
}

static void test_bbox_is_exact_and_normalises_negative_zero(void)
{
    double p[4 * 5] = {-0.0, 1, 2, 9, 0.0, -1, 2, 9, 3, 0.5, -0.0, 9, 1, 1, 1, 9, 2, -0.0, 0, 9};
    double b[6];
    sort_bbox(p, 4, NULL, 5, b, 1);
    const double want[6] = {0, -1, 0, 3, 1, 2};
    for (int a = 0; a < 6; a++)
        TEST_CHECK(b[a] == want[a] && !(b[a] == 0 && signbit(b[a])),
                   "bbox[%d] = %g (sign bit %d)", a, b[a], signbit(b[a]) != 0);
    uint32_t ids[2] = {3, 2};
    sort_bbox(p, 4, ids, 2, b, 1);
    TEST_CHECK(b[0] == 1 && b[3] == 3 && b[2] == 0 && b[5] == 1, "bbox of ids wrong");
    sort_bbox(p, 4, NULL, 0, b, 1);
    for (int a = 0; a < 6; a++)
        TEST_CHECK(b[a] == 0, "empty bbox[%d] = %g", a, b[a]);
    /* large: threads agree */
    tu_rng rng = {15};
    enum { N = 50000 };
    double *q = malloc(3 * N * sizeof *q);
    TEST_REQUIRE(q, "out of memory");
    for (int i = 0; i < 3 * N; i++)
        q[i] = (tu_uniform(&rng) - 0.5) * 1e3;
    double b1[6], b3[6];
    sort_bbox(q, 3, NULL, N, b1, 1);
    sort_bbox(q, 3, NULL, N, b3, 3);
    TEST_CHECK(memcmp(b1, b3, sizeof b1) == 0, "bbox depends on the thread count");
    free(q);
}

static void test_bbox_expand_contains_the_box_and_moves_the_partitions(void)
{
    const double box[6] = {-1, 0, 10, 3, 0, 12};  /* y is flat */
    double out[6], again[6], prev[6];
    sort_bbox_expand(box, 2.0, 7, 0, out);
    TEST_CHECK(memcmp(out, box, sizeof out) == 0, "pass 0 must return the box itself");
    sort_bbox_expand(box, 1.0, 7, 3, out);
    TEST_CHECK(memcmp(out, box, sizeof out) == 0, "factor 1 must return the box itself");
    memset(prev, 0, sizeof prev);
    for (int pass = 1; pass <= 6; pass++) {
        sort_bbox_expand(box, 2.0, 7, pass, out);
        sort_bbox_expand(box, 2.0, 7, pass, again);
        TEST_CHECK(memcmp(out, again, sizeof out) == 0, "pass %d is not deterministic", pass);
        for (int a = 0; a < 3; a++) {
            /* a flat axis grows by (factor - 1) times the largest extent, 4 */
            const double e0 = box[a + 3] - box[a], e = e0 > 0 ? e0 : 4.0;
            TEST_CHECK(out[a] <= box[a] && out[a + 3] >= box[a + 3],
                       "pass %d axis %d: [%g,%g] does not contain [%g,%g]", pass, a, out[a],
                       out[a + 3], box[a], box[a + 3]);
            TEST_CHECK(fabs((out[a + 3] - out[a]) - (e0 + e)) <= 1e-12 * e,
                       "pass %d axis %d: extent %g, want %g", pass, a, out[a + 3] - out[a],
                       e0 + e);
        }
        TEST_CHECK(memcmp(out, prev, sizeof out) != 0, "pass %d repeats the previous box", pass);
        memcpy(prev, out, sizeof out);
    }
    const double huge[6] = {-DBL_MAX, 0, 0, DBL_MAX, 1, 1};
    sort_bbox_expand(huge, 3.0, 1, 1, out);
    for (int a = 0; a < 6; a++)
        TEST_CHECK(isfinite(out[a]), "huge box: out[%d] = %g is not finite", a, out[a]);
    TEST_CHECK(out[0] == -DBL_MAX && out[3] == DBL_MAX, "huge box not clamped");
    /* in place */
    double inplace[6];
    memcpy(inplace, box, sizeof inplace);
    sort_bbox_expand(inplace, 2.0, 7, 6, inplace);
    TEST_CHECK(memcmp(inplace, prev, sizeof prev) == 0, "in-place call differs");
}

int main(void)
{
    TU_RUN(test_moore_keys_on_full_grids_are_a_face_adjacent_loop);
    TU_RUN(test_moore_key_neighbours_are_face_adjacent_at_every_depth);
    TU_RUN(test_moore_key_is_monotone_under_refinement);
    TU_RUN(test_moore_keys_clamp_points_outside_the_box);
    TU_RUN(test_moore_table_walk_equals_level_by_level_walk);
    TU_RUN(test_moore_keys_do_not_depend_on_thread_count);
    TU_RUN(test_bbox_is_exact_and_normalises_negative_zero);
    TU_RUN(test_bbox_expand_contains_the_box_and_moves_the_partitions);
    return tu_finish();
}
