/* test_sort_brio.c -- sort_brio returns a permutation cut into rounds of the specified sizes,
 * each round in Moore order of its own box, identical for any thread count and input order.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sort/sort.h"
#include "testutil.h"

static double *random_points(size_t n, uint64_t seed)
{
    tu_rng rng = {seed};
    double *p = malloc(4 * n * sizeof *p + 1);
    if (!p)
        return NULL;
    for (size_t i = 0; i < 4 * n; i++)
        p[i] = tu_uniform(&rng) * 2 - 1;
    return p;
}

/* ids 0..n-1 in a scrambled order */
static uint32_t *scrambled_ids(size_t n, uint64_t seed)
{
    tu_rng rng = {seed};
    uint32_t *ids = malloc(n * sizeof *ids + 1);
    if (!ids)
        return NULL;
    for (size_t i = 0; i < n; i++)
        ids[i] = (uint32_t)i;
    for (size_t i = n; i > 1; i--) {
        size_t j = tu_below(&rng, i);
        uint32_t t = ids[i - 1];
        ids[i - 1] = ids[j];
        ids[j] = t;
    }
    return ids;
}

/* the documented round rule */
static void check_round_ends(const size_t *end, int rounds, size_t n, size_t first, double ratio)
{
    TEST_REQUIRE(rounds >= 1 && rounds <= 64, "%d rounds", rounds);
    TEST_CHECK(end[rounds - 1] == n, "last round ends at %zu, not n=%zu", end[rounds - 1], n);
    if (rounds < 64)
        TEST_CHECK(end[0] <= first, "first round has %zu > first=%zu points", end[0], first);
    TEST_CHECK(end[0] >= 1, "empty first round");
    for (int r = 1; r < rounds; r++) {
        double q = floor((double)end[r] / ratio);
        size_t want = q < 1 ? 1 : (size_t)q;
        if (want > end[r] - 1)
            want = end[r] - 1;
        TEST_CHECK(end[r] > first, "round %d ends at %zu <= first", r, end[r]);
        TEST_CHECK(end[r - 1] == want, "round %d starts at %zu, want %zu", r, end[r - 1], want);
    }
}

static void check_brio(const double *p, size_t n, const uint32_t *in_ids, const uint32_t *out,
                       const size_t *end, int rounds)
{
    /* permutation */
    unsigned char *seen = calloc(n + 1, 1);
    TEST_REQUIRE(seen, "out of memory");
    for (size_t i = 0; i < n; i++)
        seen[in_ids[i]] = 1;
    for (size_t i = 0; i < n; i++) {
        TEST_REQUIRE(seen[out[i]] == 1, "id %u missing, repeated or foreign at %zu", out[i], i);
        seen[out[i]] = 2;
    }
    free(seen);
    /* each round in Moore order of its bounding box */
    uint64_t *key = malloc((n + 1) * sizeof *key);
    TEST_REQUIRE(key, "out of memory");
    size_t lo = 0;
    for (int r = 0; r < rounds; r++) {
        const size_t m = end[r] - lo;
        double box[6];
        sort_bbox(p, 4, out + lo, m, box, 1);
        sort_moore_keys_ids(p, 4, out + lo, m, box, sort_brio_bits(m), key, 1);
        for (size_t i = 1; i < m; i++)
            TEST_REQUIRE(key[i - 1] <= key[i], "round %d not in Moore order at %zu", r, lo + i);
        lo = end[r];
    }
    free(key);
}

static void test_brio_is_a_permutation_in_moore_ordered_rounds_of_the_specified_sizes(void)
{
    static const size_t sizes[] = {1, 2, 5, 100, 2048, 2049, 10000, 150000};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const size_t n = sizes[s];
        double *p = random_points(n, 100 + s);
        uint32_t *ids = scrambled_ids(n, 200 + s), *orig = scrambled_ids(n, 200 + s);
        TEST_REQUIRE(p && ids && orig, "out of memory");
        size_t end[64];
        int rounds = -1;
        TEST_REQUIRE(sort_brio(p, 4, ids, n, 42, 2048, 7.5, end, &rounds, 2) == GTET_OK,
                     "sort_brio failed");
        check_round_ends(end, rounds, n, 2048, 7.5);
        check_brio(p, n, orig, ids, end, rounds);
        if (n == 150000)
            TEST_CHECK(rounds == 4 && end[0] == 355 && end[1] == 2666 && end[2] == 20000,
                       "150000 points, 2048, 7.5: %d rounds, ends %zu %zu %zu", rounds, end[0],
                       end[1], end[2]);
        free(p);
        free(ids);
        free(orig);
    }
}

static void test_brio_rounds_grow_by_ratio_from_a_small_first_round(void)
{
    /* HXT's example: 10^6 points, ratio 7.5, first < 2048: 316 / 2370 / 17777 / 133333 */
    enum { N = 1000000 };
    const size_t n = N;
    double *p = malloc(4 * n * sizeof *p);
    uint32_t *ids = malloc(n * sizeof *ids);
    TEST_REQUIRE(p && ids, "out of memory");
    for (size_t i = 0; i < n; i++) {
        ids[i] = (uint32_t)i;
        for (int a = 0; a < 4; a++)
            p[4 * i + a] = (double)((i * 2654435761u + (size_t)a * 40503u) % 1000);
    }
    size_t end[64];
    int rounds;
    TEST_REQUIRE(sort_brio(p, 4, ids, n, 1, 2047, 7.5, end, &rounds, 2) == GTET_OK, "failed");
    TEST_CHECK(rounds == 5 && end[0] == 316 && end[1] == 2370 && end[2] == 17777 &&
                   end[3] == 133333 && end[4] == n,
               "rounds %d: %zu %zu %zu %zu", rounds, end[0], end[1], end[2], end[3]);
    free(p);
    free(ids);
    /* ratio close to 1: capped at 64 rounds, the smallest merged into the first */
    const size_t m = 5000;
    double *q = random_points(m, 9);
    uint32_t *qi = scrambled_ids(m, 10), *qo = scrambled_ids(m, 10);
    TEST_REQUIRE(q && qi && qo, "out of memory");
    TEST_REQUIRE(sort_brio(q, 4, qi, m, 3, 10, 1.01, end, &rounds, 1) == GTET_OK, "failed");
    TEST_CHECK(rounds == 64 && end[0] > 10, "ratio 1.01: %d rounds, first ends at %zu", rounds,
               end[0]);
    check_round_ends(end, rounds, m, 10, 1.01);
    check_brio(q, m, qo, qi, end, rounds);
    /* fewer points than `first`: one round */
    TEST_REQUIRE(sort_brio(q, 4, qi, 50, 3, 2048, 6, end, &rounds, 1) == GTET_OK, "failed");
    TEST_CHECK(rounds == 1 && end[0] == 50, "50 points: %d rounds", rounds);
    free(q);
    free(qi);
    free(qo);
}

static void test_brio_is_identical_for_any_thread_count_and_input_order(void)
{
    enum { N = 120000 };
    double *p = random_points(N, 300);
    uint32_t *ref = scrambled_ids(N, 1), *ids = scrambled_ids(N, 1),
             *other = scrambled_ids(N, 2);
    TEST_REQUIRE(p && ref && ids && other, "out of memory");
    size_t end0[64], end[64];
    int r0, r;
    TEST_REQUIRE(sort_brio(p, 4, ref, N, 77, 1000, 6, end0, &r0, 1) == GTET_OK, "failed");
    for (int t = 2; t <= 4; t++) {
        uint32_t *fresh = scrambled_ids(N, 1);
        TEST_REQUIRE(fresh, "out of memory");
        TEST_REQUIRE(sort_brio(p, 4, fresh, N, 77, 1000, 6, end, &r, t) == GTET_OK, "failed");
        TEST_CHECK(r == r0 && memcmp(end, end0, (size_t)r * sizeof *end) == 0 &&
                       memcmp(fresh, ref, N * sizeof *ref) == 0,
                   "%d threads: a different order", t);
        free(fresh);
    }
    TEST_REQUIRE(sort_brio(p, 4, other, N, 77, 1000, 6, end, &r, 3) == GTET_OK, "failed");
    TEST_CHECK(memcmp(other, ref, N * sizeof *ref) == 0, "the order depends on the input order");
    /* another seed gives another order */
    TEST_REQUIRE(sort_brio(p, 4, ids, N, 78, 1000, 6, end, &r, 2) == GTET_OK, "failed");
    TEST_CHECK(memcmp(ids, ref, N * sizeof *ref) != 0, "seeds 77 and 78 give the same order");
    free(p);
    free(ref);
    free(ids);
    free(other);
}

static void test_brio_breaks_ties_in_a_moore_cell_by_the_shuffle_hash(void)
{
    /* 40000 points on 27 positions: every Moore cell holds long runs of equal keys */
    enum { N = 40000 };
    double *p = malloc(4 * N * sizeof *p);
    uint32_t *ids = scrambled_ids(N, 5), *orig = scrambled_ids(N, 5), *other = scrambled_ids(N, 6);
    uint64_t *key = malloc(N * sizeof *key);
    TEST_REQUIRE(p && ids && orig && other && key, "out of memory");
    tu_rng rng = {77};
    for (size_t i = 0; i < 4 * (size_t)N; i++)
        p[i] = (double)tu_below(&rng, 3);
    size_t end[64], end2[64];
    int rounds, rounds2;
    TEST_REQUIRE(sort_brio(p, 4, ids, N, 9, 100, 4, end, &rounds, 2) == GTET_OK, "failed");
    check_round_ends(end, rounds, N, 100, 4);
    check_brio(p, N, orig, ids, end, rounds);
    const uint64_t salt = sort_hash64(9);
    size_t lo = 0, ties = 0;
    for (int r = 0; r < rounds; r++) {
        const size_t m = end[r] - lo;
        double box[6];
        sort_bbox(p, 4, ids + lo, m, box, 1);
        sort_moore_keys_ids(p, 4, ids + lo, m, box, sort_brio_bits(m), key, 1);
        for (size_t i = 1; i < m; i++)
            if (key[i - 1] == key[i]) {
                ties++;
                TEST_REQUIRE(sort_hash64(ids[lo + i - 1] + salt) < sort_hash64(ids[lo + i] + salt),
                             "round %d: equal keys not in hash order at %zu", r, lo + i);
            }
        lo = end[r];
    }
    TEST_CHECK(ties > N / 2, "only %zu ties: the test does not test ties", ties);
    TEST_REQUIRE(sort_brio(p, 4, other, N, 9, 100, 4, end2, &rounds2, 1) == GTET_OK, "failed");
    TEST_CHECK(memcmp(other, ids, N * sizeof *ids) == 0,
               "with ties, the order depends on the input order or the thread count");
    free(p);
    free(ids);
    free(orig);
    free(other);
    free(key);
}

typedef struct ref_item {
    uint64_t key;
    uint32_t id, pos;
} ref_item;

static int ref_cmp(const void *a, const void *b)
{
    const ref_item *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->pos < y->pos ? -1 : x->pos > y->pos;
}

/* The definition of sort.h, literally: qsort by hash, cut with the documented rule, each round
 * stably qsorted by its Moore key. */
static void reference_brio(const double *p, uint32_t *ids, size_t n, uint64_t seed, size_t first,
                           double ratio)
{
    ref_item *it = malloc(n * sizeof *it);
    uint64_t *key = malloc(n * sizeof *key);
    if (!it || !key) {
        TEST_CHECK(0, "out of memory");
        return;
    }
    const uint64_t salt = sort_hash64(seed);
    for (size_t i = 0; i < n; i++)
        it[i] = (ref_item){sort_hash64(ids[i] + salt), ids[i], (uint32_t)i};
    qsort(it, n, sizeof *it, ref_cmp);
    for (size_t i = 0; i < n; i++)
        ids[i] = it[i].id;
    size_t down[64];
    int r = 0;
    down[r++] = n;
    while (down[r - 1] > first && r < 64) {
        double q = floor((double)down[r - 1] / ratio);
        size_t nx = q < 1 ? 1 : (size_t)q;
        down[r] = nx > down[r - 1] - 1 ? down[r - 1] - 1 : nx;
        r++;
    }
    size_t lo = 0;
    for (int k = r - 1; k >= 0; k--) {
        const size_t m = down[k] - lo;
        double box[6];
        sort_bbox(p, 4, ids + lo, m, box, 1);
        sort_moore_keys_ids(p, 4, ids + lo, m, box, sort_brio_bits(m), key, 1);
        for (size_t i = 0; i < m; i++)
            it[i] = (ref_item){key[i], ids[lo + i], (uint32_t)i};
        qsort(it, m, sizeof *it, ref_cmp);
        for (size_t i = 0; i < m; i++)
            ids[lo + i] = it[i].id;
        lo = down[k];
    }
    free(it);
    free(key);
}

static void test_brio_equals_the_literal_definition(void)
{
    static const size_t sizes[] = {1, 7, 3000, 60000};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        for (int ties = 0; ties < 2; ties++) {
            const size_t n = sizes[s];
            double *p = random_points(n, 500 + s);
            uint32_t *ids = scrambled_ids(n, 600 + s), *ref = scrambled_ids(n, 600 + s);
            TEST_REQUIRE(p && ids && ref, "out of memory");
            if (ties)
                for (size_t i = 0; i < 4 * n; i++)
                    p[i] = floor(p[i] * 3);
            reference_brio(p, ref, n, 31, 500, 5.5);
            size_t end[64];
            int rounds;
            TEST_REQUIRE(sort_brio(p, 4, ids, n, 31, 500, 5.5, end, &rounds, 2) == GTET_OK,
                         "failed");
            TEST_CHECK(memcmp(ids, ref, n * sizeof *ids) == 0,
                       "n=%zu ties=%d: sort_brio differs from the literal definition", n, ties);
            free(p);
            free(ids);
            free(ref);
        }
    }
}

static void test_brio_rejects_bad_arguments(void)
{
    double p[8] = {0};
    uint32_t ids[2] = {0, 1};
    size_t end[64];
    int r = 5;
    TEST_CHECK(sort_brio(p, 4, ids, 0, 1, 10, 6, end, &r, 1) == GTET_OK && r == 0, "n=0");
    TEST_CHECK(sort_brio(p, 4, ids, 2, 1, 0, 6, end, &r, 1) == GTET_ERR_ARGUMENT, "first=0");
    TEST_CHECK(sort_brio(p, 4, ids, 2, 1, 10, 1.0, end, &r, 1) == GTET_ERR_ARGUMENT, "ratio 1");
    TEST_CHECK(sort_brio(p, 4, ids, 2, 1, 10, NAN, end, &r, 1) == GTET_ERR_ARGUMENT, "NaN");
    TEST_CHECK(sort_brio(NULL, 4, ids, 2, 1, 10, 6, end, &r, 1) == GTET_ERR_ARGUMENT, "NULL");
    TEST_CHECK(sort_brio(p, 4, ids, 2, 1, 10, 6, end, NULL, 1) == GTET_ERR_ARGUMENT, "NULL");
    TEST_CHECK(sort_brio_bits(1) == 3 && sort_brio_bits(8) == 4 && sort_brio_bits(1000000) == 10 &&
                   sort_brio_bits((size_t)1 << 62) == 21,
               "sort_brio_bits: %d %d %d", sort_brio_bits(1), sort_brio_bits(8),
               sort_brio_bits(1000000));
}

int main(void)
{
    TU_RUN(test_brio_is_a_permutation_in_moore_ordered_rounds_of_the_specified_sizes);
    TU_RUN(test_brio_rounds_grow_by_ratio_from_a_small_first_round);
    TU_RUN(test_brio_is_identical_for_any_thread_count_and_input_order);
    TU_RUN(test_brio_breaks_ties_in_a_moore_cell_by_the_shuffle_hash);
    TU_RUN(test_brio_equals_the_literal_definition);
    TU_RUN(test_brio_rejects_bad_arguments);
    return tu_finish();
}
