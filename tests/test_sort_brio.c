/* test_sort_brio.c -- sort_brio returns a permutation cut into rounds of the specified sizes,
 * each round in Moore order of the set's box, long runs in one Moore cell refined on their own
 * box, identical for any thread count and input order; sort_brio_keys gives those keys.
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
    /* each round in Moore order of the set's bounding box */
    uint64_t *key = malloc((n + 1) * sizeof *key);
    TEST_REQUIRE(key, "out of memory");
    double box[6];
    sort_bbox(p, 4, out, n, box, 1);
    size_t lo = 0;
    for (int r = 0; r < rounds; r++) {
        const size_t m = end[r] - lo;
        sort_moore_keys_ids(p, 4, out + lo, m, box, sort_brio_bits(n), key, 1);
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
    double box[6];
    sort_bbox(p, 4, ids, N, box, 1);
    for (int r = 0; r < rounds; r++) {
        const size_t m = end[r] - lo;
        /* runs of coincident points: nothing to refine, so hash order */
        sort_moore_keys_ids(p, 4, ids + lo, m, box, sort_brio_bits(N), key, 1);
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

/* ids[0..m) sorted stably by their Moore keys on box with `bits` bits (qsort on (key, pos));
 * keys_sorted[i] gets the key of the point now at i */
static void ref_sort_by_key(const double *p, uint32_t *ids, size_t m, const double box[6],
                            int bits, ref_item *it, uint64_t *key, uint64_t *keys_sorted)
{
    sort_moore_keys_ids(p, 4, ids, m, box, bits, key, 1);
    for (size_t i = 0; i < m; i++)
        it[i] = (ref_item){key[i], ids[i], (uint32_t)i};
    qsort(it, m, sizeof *it, ref_cmp);
    for (size_t i = 0; i < m; i++) {
        ids[i] = it[i].id;
        keys_sorted[i] = it[i].key;
    }
}

/* sort.h's refinement, literally: runs of more than 32 equal keys (ks) sorted by the 21-bit
 * keys on the set's box `all` (level 1, when the round's keys had fewer bits, kb < 21), then
 * on their own box, recursively, to 32 levels in all; ks is consumed */
static void ref_refine_runs(const double *p, uint32_t *ids, const uint64_t *ks, size_t m,
                            int depth, const double all[6], int kb, ref_item *it, uint64_t *key)
{
    for (size_t i = 0; i < m;) {
        size_t j = i + 1;
        while (j < m && ks[j] == ks[i])
            j++;
        int fine = 0;  /* sort.h: the fine keys' level when the run is wide enough */
        if (j - i > 32 && depth == 1 && kb < 21) {
            double rb[6];
            sort_bbox(p, 4, ids + i, j - i, rb, 1);
            for (int a = 0; a < 3; a++)
                fine |= rb[a + 3] - rb[a] >= ldexp(1.0, sort_brio_bits(j - i) - 22) *
                                                  (all[a + 3] - all[a]) &&
                        rb[a + 3] > rb[a];
        }
        if (fine) {
            uint64_t *sub = malloc((j - i) * sizeof *sub);
            TEST_REQUIRE(sub, "out of memory");
            ref_sort_by_key(p, ids + i, j - i, all, 21, it, key, sub);
            ref_refine_runs(p, ids + i, sub, j - i, depth + 1, all, kb, it, key);
            free(sub);
        } else if (j - i > 32 && depth <= 32) {
            double box[6];
            sort_bbox(p, 4, ids + i, j - i, box, 1);
            if (!(box[0] == box[3] && box[1] == box[4] && box[2] == box[5])) {
                uint64_t *sub = malloc((j - i) * sizeof *sub);
                TEST_REQUIRE(sub, "out of memory");
                ref_sort_by_key(p, ids + i, j - i, box, sort_brio_bits(j - i), it, key, sub);
                ref_refine_runs(p, ids + i, sub, j - i, depth + 1, all, kb, it, key);
                free(sub);
            }
        }
        i = j;
    }
}

/* The definition of sort.h, literally: qsort by hash, cut with the documented rule, each round
 * stably qsorted by its Moore key on the set's box, long runs refined. */
static void reference_brio(const double *p, uint32_t *ids, size_t n, uint64_t seed, size_t first,
                           double ratio)
{
    ref_item *it = malloc((n + 1) * sizeof *it);
    uint64_t *key = malloc((n + 1) * sizeof *key), *ks = malloc((n + 1) * sizeof *ks);
    if (!it || !key || !ks) {
        TEST_CHECK(0, "out of memory");
        return;
    }
    double box[6];
    sort_bbox(p, 4, ids, n, box, 1);
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
        ref_sort_by_key(p, ids + lo, m, box, sort_brio_bits(n), it, key, ks);
        ref_refine_runs(p, ids + lo, ks, m, 1, box, sort_brio_bits(n), it, key);
        lo = down[k];
    }
    free(it);
    free(key);
    free(ks);
}

/* kind 0: uniform; 1: 27 positions (ties); 2: one point far away (the rest in one Moore cell:
 * refined); 3: nested clusters, 10^-4 and 10^-9 wide (refined on two and more levels); 4: half
 * the points in a cube 10^-3 wide (refined by the fine keys, sort.h) */
static void shape_points(double *p, size_t n, int kind)
{
    if (kind == 1)
        for (size_t i = 0; i < 4 * n; i++)
            p[i] = floor(p[i] * 3);
    if (kind == 2 && n > 0)
        p[0] = p[1] = p[2] = 1e9;
    if (kind == 4)
        for (size_t i = 0; i < n; i += 2)
            for (int a = 0; a < 3; a++)
                p[4 * i + a] = 0.25 + p[4 * i + a] * 1e-3;
    if (kind == 3)
        for (size_t i = 0; i < n; i++) {
            const double s = i % 3 == 0 ? 1.0 : i % 3 == 1 ? 1e-4 : 1e-9;
            for (int a = 0; a < 3; a++)
                p[4 * i + a] = 0.25 + p[4 * i + a] * s;
        }
}

static void test_brio_equals_the_literal_definition(void)
{
    static const size_t sizes[] = {1, 7, 3000, 60000};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        for (int kind = 0; kind < 5; kind++) {
            const size_t n = sizes[s];
            double *p = random_points(n, 500 + s);
            uint32_t *ids = scrambled_ids(n, 600 + s), *ref = scrambled_ids(n, 600 + s);
            TEST_REQUIRE(p && ids && ref, "out of memory");
            shape_points(p, n, kind);
            reference_brio(p, ref, n, 31, 500, 5.5);
            size_t end[64];
            int rounds;
            TEST_REQUIRE(sort_brio(p, 4, ids, n, 31, 500, 5.5, end, &rounds, 2) == GTET_OK,
                         "failed");
            TEST_CHECK(memcmp(ids, ref, n * sizeof *ids) == 0,
                       "n=%zu kind %d: sort_brio differs from the literal definition", n, kind);
            free(p);
            free(ids);
            free(ref);
        }
    }
}

/* mean distance between consecutive points of ids[lo..hi) that both lie within `radius` of
 * (0.25, 0.25, 0.25) in every coordinate */
static double mean_step(const double *p, const uint32_t *ids, size_t lo, size_t hi, double radius)
{
    double sum = 0;
    size_t cnt = 0;
    for (size_t i = lo + 1; i < hi; i++) {
        const double *a = p + 4 * (size_t)ids[i - 1], *b = p + 4 * (size_t)ids[i];
        int in = 1;
        for (int k = 0; k < 3; k++)
            in &= fabs(a[k] - 0.25) <= radius && fabs(b[k] - 0.25) <= radius;
        if (!in)
            continue;
        sum += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                    (a[2] - b[2]) * (a[2] - b[2]));
        cnt++;
    }
    return cnt ? sum / (double)cnt : 0;
}

static void test_brio_orders_a_set_with_a_far_point_as_finely_as_without(void)
{
    /* the issue behind the refinement: with one point at 10^9 every other point is in one
     * Moore cell of the box, and hash order there is random order (a walk across the mesh per
     * insertion); refined, consecutive points are as close as in the uniform set.  The same
     * inside nested clusters: the third of the points in a cube 10^-9 wide (two levels down)
     * is ordered at its own scale (its spacing is cbrt(3) times the full set's, scaled) */
    enum { N = 100000 };
    double *p = random_points(N, 900);
    uint32_t *ids = scrambled_ids(N, 901), *uni = scrambled_ids(N, 901);
    TEST_REQUIRE(p && ids && uni, "out of memory");
    size_t end[64];
    int rounds;
    TEST_REQUIRE(sort_brio(p, 4, uni, N, 5, 1000, 6, end, &rounds, 2) == GTET_OK, "failed");
    const double base = mean_step(p, uni, end[rounds - 2], end[rounds - 1], 2.0);
    double *q = malloc(4 * N * sizeof *q);
    TEST_REQUIRE(q, "out of memory");
    for (int kind = 2; kind <= 3; kind++) {
        memcpy(q, p, 4 * N * sizeof *q);
        shape_points(q, N, kind);
        memcpy(ids, uni, N * sizeof *ids);
        TEST_REQUIRE(sort_brio(q, 4, ids, N, 5, 1000, 6, end, &rounds, 2) == GTET_OK, "failed");
        const double scale = kind == 2 ? 1.0 : 1e-9;
        const double step = mean_step(q, ids, end[rounds - 2], end[rounds - 1],
                                      kind == 2 ? 1.0 : 2e-9);
        const double bound = (kind == 2 ? 1.5 : 1.5 * cbrt(3.0)) * base * scale;
        TEST_CHECK(step > 0 && step < bound, "kind %d: mean step %g, bound %g (uniform: %g)",
                   kind, step, bound, base);
    }
    free(q);
    free(p);
    free(ids);
    free(uni);
}

static void test_brio_keys_are_the_moore_keys_on_the_sets_box(void)
{
    enum { N = 50000 };
    for (int kind = 0; kind < 5; kind += 2) {
        double *p = random_points(N, 910);
        uint32_t *ids = scrambled_ids(N, 911), *ref = scrambled_ids(N, 911);
        uint64_t *want = malloc(N * sizeof *want);
        TEST_REQUIRE(p && ids && ref && want, "out of memory");
        shape_points(p, N, kind);
        size_t end[64], end2[64], refined = 12345;
        double crowd = -1;
        int rounds, rounds2, bits = 0;
        uint64_t *keys = NULL;
        TEST_REQUIRE(sort_brio(p, 4, ref, N, 8, 700, 6, end, &rounds, 1) == GTET_OK, "failed");
        TEST_REQUIRE(sort_brio_keys(p, 4, ids, N, 8, 700, 6, end2, &rounds2, 2, &keys, &bits,
                                    &refined, &crowd) == GTET_OK && keys,
                     "sort_brio_keys failed");
        TEST_CHECK(rounds2 == rounds && memcmp(ids, ref, N * sizeof *ids) == 0,
                   "sort_brio_keys orders differently from sort_brio");
        TEST_CHECK(bits == 21, "bits %d", bits);
        TEST_CHECK(kind == 0   ? refined == 0
                   : kind == 2 ? refined >= N - 1 - N / 700
                               : refined >= N / 2 - N / 100 && refined <= N / 2,
                   "kind %d: %zu points refined", kind, refined);
        /* uniform: about 1/512 point per cell; a far point: the rest of each round in one
         * (and in a few fine cells: not refined by them); the cluster: in fine cells of a few
         * points each */
        TEST_CHECK(kind == 2 ? crowd > 0.99 : crowd > 0 && crowd < 0.01, "kind %d: crowd %g",
                   kind, crowd);
        /* a point of a refined run (more than 32 of a round in one cell of sort_brio_bits(N)
         * bits): its 21-bit key; any other: its key with those bits shifted up to 21 bits */
        double box[6];
        sort_bbox(p, 4, ids, N, box, 1);
        const int b = sort_brio_bits(N);
        uint64_t *fine = malloc(N * sizeof *fine);
        TEST_REQUIRE(fine, "out of memory");
        sort_moore_keys_ids(p, 4, ids, N, box, b, want, 1);
        sort_moore_keys_ids(p, 4, ids, N, box, 21, fine, 1);
        size_t bad = 0, down = 0;
        int r = 0;
        for (size_t i = 0; i < N;) {
            while (i >= end[r])
                r++;
            size_t j = i + 1;
            while (j < end[r] && want[j] == want[i])
                j++;
            for (size_t u = i; u < j; u++) {
                bad += keys[u] != (j - i > 32 && kind == 4 ? fine[u] : want[u] << (3 * (21 - b)));
                down += u > (r ? end[r - 1] : 0) && keys[u] < keys[u - 1];
            }
            i = j;
        }
        free(fine);
        TEST_CHECK(bad == 0 && down == 0, "kind %d: %zu keys differ, %zu decrease", kind, bad,
                   down);
        free(keys);
        free(p);
        free(ids);
        free(ref);
        free(want);
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
    TU_RUN(test_brio_orders_a_set_with_a_far_point_as_finely_as_without);
    TU_RUN(test_brio_keys_are_the_moore_keys_on_the_sets_box);
    TU_RUN(test_brio_rejects_bad_arguments);
    return tu_finish();
}
