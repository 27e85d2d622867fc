/* test_validate_dedup.c -- exact duplicate detection (src/validate/validate.c): the single-table
 * pass kval_dedup uses below 65536 points and the partitioned one it uses above, on 1-4
 * threads, against a definition computed here by sorting.
 *
 * Specification (validate.h): two points are duplicates exactly when their coordinates
 * compare equal with == (so -0.0 and +0.0 are equal); the vertices are the first occurrences,
 * in input order, with the coordinates (signed zeros included) of the first occurrence; map[i]
 * is the vertex of point i.  The reference sorts the indices by coordinates (folding -0.0 onto
 * +0.0) and then by index, so each run of equal points starts with its first occurrence.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "validate/validate.h"
#include "testutil.h"

static const double *g_pts;

static double fold(double x) { return x == 0.0 ? 0.0 : x; }

static int cmp_point(const void *a, const void *b)
{
    const uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;
    for (int d = 0; d < 3; d++) {
        const double x = fold(g_pts[3 * (size_t)i + d]), y = fold(g_pts[3 * (size_t)j + d]);
        if (x != y) return x < y ? -1 : 1;
    }
    return (i > j) - (i < j);
}

/* The reference map and vertex count. */
static uint32_t *reference(const double *p, size_t n, size_t *nv)
{
    uint32_t *idx = malloc((n ? n : 1) * sizeof *idx), *first = malloc((n ? n : 1) * sizeof *first);
    uint32_t *map = malloc((n ? n : 1) * sizeof *map);
    for (size_t i = 0; i < n; i++) idx[i] = (uint32_t)i;
    g_pts = p;
    qsort(idx, n, sizeof *idx, cmp_point);
    for (size_t k = 0; k < n; k++) {  /* first[i] = first occurrence of i's point */
        const int same = k > 0 && fold(p[3 * (size_t)idx[k]]) == fold(p[3 * (size_t)idx[k - 1]]) &&
                         fold(p[3 * (size_t)idx[k] + 1]) == fold(p[3 * (size_t)idx[k - 1] + 1]) &&
                         fold(p[3 * (size_t)idx[k] + 2]) == fold(p[3 * (size_t)idx[k - 1] + 2]);
        first[idx[k]] = same ? first[idx[k - 1]] : idx[k];
    }
    size_t next = 0;
    for (size_t i = 0; i < n; i++) map[i] = first[i] == i ? (uint32_t)next++ : map[first[i]];
    *nv = next;
    free(idx);
    free(first);
    return map;
}

static void expect_same(const char *what, const double *p, size_t n, const uint32_t *rmap,
                        size_t rnv, int method, int T)
{
    double *v = NULL;
    uint32_t *map = NULL;
    size_t nv = 0;
    gtet_error err;
    const gtet_status s = method ? kval_dedup_partitioned(p, n, T, &v, &map, &nv, &err)
                                 : kval_dedup(p, n, T, &v, &map, &nv, &err);
    TEST_REQUIRE(s == GTET_OK, "%s, %s, %d threads: %s", what, method ? "partitioned" : "kval_dedup",
                 T, gtet_status_str(s));
    TEST_CHECK(nv == rnv, "%s, %s, %d threads: %zu vertices, not %zu", what,
               method ? "partitioned" : "kval_dedup", T, nv, rnv);
    size_t bad = 0, first_bad = SIZE_MAX;
    for (size_t i = 0; i < n && nv == rnv; i++) {
        if (map[i] != rmap[i]) {
            bad++;
            if (first_bad == SIZE_MAX) first_bad = i;
        }
    }
    TEST_CHECK(bad == 0, "%s, %s, %d threads: %zu points mapped wrongly, first %zu", what,
               method ? "partitioned" : "kval_dedup", T, bad, first_bad);
    /* the vertex of each first occurrence holds its coordinates bit for bit */
    if (nv == rnv) {
        uint8_t *seen = calloc(nv ? nv : 1, 1);
        size_t wrong = 0;
        for (size_t i = 0; i < n; i++) {
            if (seen[rmap[i]]) continue;
            seen[rmap[i]] = 1;
            wrong += memcmp(v + 3 * (size_t)rmap[i], p + 3 * i, 3 * sizeof *p) != 0;
        }
        TEST_CHECK(wrong == 0, "%s, %s, %d threads: %zu vertices differ from their first occurrence",
                   what, method ? "partitioned" : "kval_dedup", T, wrong);
        free(seen);
    }
    free(v);
    free(map);
}

static void check_set(const char *what, const double *p, size_t n)
{
    size_t rnv;
    uint32_t *rmap = reference(p, n, &rnv);
    for (int T = 1; T <= 4; T++) {
        expect_same(what, p, n, rmap, rnv, 0, T);
        expect_same(what, p, n, rmap, rnv, 1, T);
    }
    free(rmap);
}

/* n points drawn from `distinct` integer points in [-20, 20)^3, zeros signed at random: long
 * runs of duplicates in every bucket, equal points in different threads' chunks. */
static double *with_duplicates(size_t n, size_t distinct, uint64_t seed)
{
    tu_rng r = {seed};
    double *d = malloc(3 * distinct * sizeof *d), *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < 3 * distinct; i++) d[i] = (double)tu_below(&r, 40) - 20;
    for (size_t i = 0; i < n; i++) {
        const size_t k = tu_below(&r, distinct);
        for (int j = 0; j < 3; j++) {
            double x = d[3 * k + (size_t)j];
            if (x == 0 && tu_below(&r, 2)) x = -0.0;
            p[3 * i + (size_t)j] = x;
        }
    }
    free(d);
    return p;
}

static void test_many_duplicates_in_every_bucket(void)
{
    const size_t n = 200000;
    double *p = with_duplicates(n, 3000, 7);
    check_set("200k from 3000 distinct", p, n);
    free(p);
    /* few duplicates: most buckets hold only distinct points */
    p = with_duplicates(n, 60000, 8);
    check_set("200k from 60000 distinct", p, n);
    free(p);
}

static void test_distinct_points_are_all_kept_in_order(void)
{
    const size_t n = 150000;
    tu_rng r = {99};
    double *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < 3 * n; i++) p[i] = tu_uniform(&r);
    check_set("150k uniform", p, n);
    /* neighbours in the last bit: equal but for one ulp must stay apart */
    for (size_t i = 1; i < n; i += 2) {
        memcpy(p + 3 * i, p + 3 * (i - 1), 3 * sizeof *p);
        p[3 * i + (i % 3)] = nextafter(p[3 * i + (i % 3)], 2.0);
    }
    check_set("150k in pairs one ulp apart", p, n);
    free(p);
}

/* Every point equal (signed zeros mixed): one bucket holds them all, on one thread. */
static void test_all_points_equal_fall_in_one_bucket(void)
{
    const size_t n = 100000;
    double *p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < n; i++) {
        p[3 * i] = (i & 1) ? -0.0 : 0.0;
        p[3 * i + 1] = 1.5;
        p[3 * i + 2] = (i & 2) ? -0.0 : 0.0;
    }
    check_set("100k equal", p, n);
    free(p);
}

/* The partitioned pass also on sets so small that it has one bucket (and chunks of a few
 * points), and on none. */
static void test_small_sets(void)
{
    const size_t sizes[] = {0, 1, 2, 5, 17, 1000, 20000};
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        double *p = with_duplicates(sizes[k] ? sizes[k] : 1, sizes[k] / 3 + 1, 100 + k);
        char what[32];
        snprintf(what, sizeof what, "%zu points", sizes[k]);
        check_set(what, p, sizes[k]);
        free(p);
    }
}

int main(void)
{
    TU_RUN(test_many_duplicates_in_every_bucket);
    TU_RUN(test_distinct_points_are_all_kept_in_order);
    TU_RUN(test_all_points_equal_fall_in_one_bucket);
    TU_RUN(test_small_sets);
    return tu_finish();
}
