/* test_sort_radix.c -- sort_radix_pairs is the stable sort on the low key_bits bits, for every
 * size regime (insertion, serial LSD, parallel LSD, MSD hybrid, skewed buckets) and thread
 * count.
 *
 * The reference is qsort on (key & mask, original position): with the position as tie-break
 * this is the unique stable order, so equality with it checks order and stability at once.
 * The keys carry random bits above key_bits, which the sort must ignore but carry along.
 * sort_radix_pairs_grouped (keys sorted but inside groups) gives the same order.
 */
#include <stdlib.h>
#include <string.h>

#include "sort/sort.h"
#include "testutil.h"

typedef struct ref_item {
    uint64_t key, masked;
    uint32_t idx, pos;
} ref_item;

static int ref_cmp(const void *a, const void *b)
{
    const ref_item *x = a, *y = b;
    if (x->masked != y->masked)
        return x->masked < y->masked ? -1 : 1;
    return x->pos < y->pos ? -1 : x->pos > y->pos;
}

static uint64_t mask_of(int bits)
{
    return bits >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << bits) - 1u);
}

enum dist { UNIFORM, FEW_VALUES, SKEWED, CONSTANT_HIGH };

static void fill(uint64_t *k, uint32_t *ix, size_t n, int bits, enum dist d, tu_rng *rng)
{
    const uint64_t m = mask_of(bits);
    for (size_t i = 0; i < n; i++) {
        uint64_t v = tu_next(rng);
        uint64_t garbage = v & ~m;  /* bits the sort must ignore */
        switch (d) {
        case UNIFORM: break;
        case FEW_VALUES: v = tu_below(rng, 4) * (m / 3); break;
        case SKEWED:  /* 90% share the top digit */
            if (tu_below(rng, 10) != 0)
                v = (m >> (bits > 11 ? 11 : 1)) & v;
            break;
        case CONSTANT_HIGH: v &= m >> (bits > 24 ? 24 : bits / 2); break;
        }
        k[i] = (v & m) | garbage;
        ix[i] = (uint32_t)(tu_next(rng) >> 32);
    }
}

/* sorts a copy and compares with the reference; returns 1 if equal */
static int check_case(size_t n, int bits, enum dist d, int threads, uint64_t seed)
{
    tu_rng rng = {seed};
    const size_t a = n ? n : 1;
    uint64_t *k = malloc(a * sizeof *k), *tk = malloc(a * sizeof *tk);
    uint32_t *ix = malloc(a * sizeof *ix), *ti = malloc(a * sizeof *ti);
    ref_item *ref = malloc(a * sizeof *ref);
    int ok = 1;
    if (!k || !tk || !ix || !ti || !ref) {
        TEST_CHECK(0, "out of memory");
        ok = 0;
        goto out;
    }
    fill(k, ix, n, bits, d, &rng);
    const uint64_t m = mask_of(bits > 64 ? 64 : bits);
    for (size_t i = 0; i < n; i++)
        ref[i] = (ref_item){k[i], k[i] & m, ix[i], (uint32_t)i};
    qsort(ref, n, sizeof *ref, ref_cmp);
    sort_radix_pairs(k, ix, n, bits, tk, ti, threads);
    for (size_t i = 0; i < n; i++) {
        if (k[i] != ref[i].key || ix[i] != ref[i].idx) {
            TEST_CHECK(0, "n=%zu bits=%d dist=%d threads=%d: first difference at %zu", n, bits,
                       (int)d, threads, i);
            ok = 0;
            break;
        }
    }
out:
    free(k);
    free(tk);
    free(ix);
    free(ti);
    free(ref);
    return ok;
}

static void test_radix_equals_stable_reference_at_boundary_sizes(void)
{
    static const size_t sizes[] = {0, 1, 2, 3, 63, 64, 65, 100, 1000, 32767, 32768, 32769,
                                   65535, 65536, 65537, 200000};
    static const int bits[] = {64, 63, 33, 30, 12, 11, 5, 1};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (size_t b = 0; b < sizeof bits / sizeof bits[0]; b++)
            if (sizes[s] < 32767 || bits[b] == 64 || bits[b] == 33 || bits[b] == 11)
                check_case(sizes[s], bits[b], UNIFORM, sizes[s] >= 32768 ? 2 : 1,
                           1000 + s * 16 + b);
}

static void test_radix_equals_reference_on_few_distinct_values_and_skewed_keys(void)
{
    static const size_t sizes[] = {65, 5000, 40000, 150000};
    static const int bits[] = {64, 40, 22, 11};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (size_t b = 0; b < sizeof bits / sizeof bits[0]; b++)
            for (int d = FEW_VALUES; d <= CONSTANT_HIGH; d++)
                check_case(sizes[s], bits[b], (enum dist)d, 1 + (int)((s + b + (size_t)d) % 3),
                           2000 + s * 64 + b * 4 + (size_t)d);
}

static void test_radix_sorts_one_million_keys_like_the_reference(void)
{
    check_case(1000000, 63, UNIFORM, 1, 3001);
    check_case(1000000, 33, SKEWED, 4, 3003);
}

static void test_radix_is_stable_on_equal_keys(void)
{
    enum { N = 100000 };
    uint64_t *k = malloc(N * sizeof *k), *tk = malloc(N * sizeof *tk);
    uint32_t *ix = malloc(N * sizeof *ix), *ti = malloc(N * sizeof *ti);
    TEST_REQUIRE(k && tk && ix && ti, "out of memory");
    tu_rng rng = {4};
    for (uint32_t i = 0; i < N; i++) {
        k[i] = tu_below(&rng, 7) << 40 | (tu_next(&rng) << 50);  /* 7 values on 50 bits */
        ix[i] = i;
    }
    sort_radix_pairs(k, ix, N, 50, tk, ti, 2);
    const uint64_t m = mask_of(50);
    for (size_t i = 1; i < N; i++) {
        TEST_REQUIRE((k[i - 1] & m) <= (k[i] & m), "not sorted at %zu", i);
        if ((k[i - 1] & m) == (k[i] & m))
            TEST_REQUIRE(ix[i - 1] < ix[i], "equal keys out of input order at %zu", i);
    }
    free(k);
    free(tk);
    free(ix);
    free(ti);
}

static void test_radix_output_is_identical_for_threads_1_to_4(void)
{
    static const size_t sizes[] = {40000, 300000};
    for (size_t s = 0; s < 2; s++) {
        const size_t n = sizes[s];
        uint64_t *k0 = malloc(n * sizeof *k0), *k = malloc(n * sizeof *k),
                 *tk = malloc(n * sizeof *tk);
        uint32_t *i0 = malloc(n * sizeof *i0), *ix = malloc(n * sizeof *ix),
                 *ti = malloc(n * sizeof *ti);
        TEST_REQUIRE(k0 && k && tk && i0 && ix && ti, "out of memory");
        tu_rng rng = {5 + s};
        fill(k0, i0, n, 45, UNIFORM, &rng);
        uint64_t *rk = malloc(n * sizeof *rk);
        uint32_t *ri = malloc(n * sizeof *ri);
        TEST_REQUIRE(rk && ri, "out of memory");
        for (int t = 1; t <= 4; t++) {
            memcpy(k, k0, n * sizeof *k);
            memcpy(ix, i0, n * sizeof *ix);
            sort_radix_pairs(k, ix, n, 45, tk, ti, t);
            if (t == 1) {
                memcpy(rk, k, n * sizeof *k);
                memcpy(ri, ix, n * sizeof *ix);
            } else {
                TEST_CHECK(memcmp(rk, k, n * sizeof *k) == 0 &&
                               memcmp(ri, ix, n * sizeof *ix) == 0,
                           "n=%zu: %d threads differ from 1 thread", n, t);
            }
        }
        free(k0); free(k); free(tk); free(i0); free(ix); free(ti); free(rk); free(ri);
    }
}

static void test_radix_ignores_zero_bits_and_clamps_large_key_bits(void)
{
    uint64_t k[3] = {3, 1, 2}, tk[3];
    uint32_t ix[3] = {0, 1, 2}, ti[3];
    sort_radix_pairs(k, ix, 3, 0, tk, ti, 1);
    TEST_CHECK(k[0] == 3 && ix[0] == 0 && ix[2] == 2, "key_bits=0 must not move anything");
    check_case(1000, 100, UNIFORM, 1, 6);
    check_case(70000, 100, UNIFORM, 2, 7);
}

/* sort_radix_pairs_grouped (NOTES.md E101) gives sort_radix_pairs's result on keys sorted but
 * inside groups: groups of every size (1 to 200k keys) sharing their bits above `low`, in
 * ascending order of those bits, each group shuffled or left sorted; also an already sorted
 * input, a fully shuffled one, and descents at the top bit. */
static void check_grouped(size_t n, int bits, int low, size_t group_max, int threads,
                          uint64_t seed, const char *what)
{
    tu_rng rng = {seed};
    const uint64_t m = mask_of(bits);
    uint64_t *k = malloc(n * sizeof *k), *tk = malloc(n * sizeof *tk), *rk = malloc(n * sizeof *rk);
    uint32_t *ix = malloc(n * sizeof *ix), *ti = malloc(n * sizeof *ti), *ri = malloc(n * sizeof *ri);
    TEST_REQUIRE(k && tk && rk && ix && ti && ri, "out of memory");
    uint64_t top = 0;
    for (size_t i = 0; i < n;) {
        const size_t g = 1 + (size_t)tu_below(&rng, group_max);
        const int shuffled = tu_below(&rng, 3) != 0;
        uint64_t at = 0;
        for (size_t j = i; j < n && j < i + g; j++) {
            at += tu_below(&rng, 3);  /* ascending low bits, with ties, unless shuffled */
            const uint64_t lowbits = low >= 64 ? tu_next(&rng) : shuffled
                ? tu_next(&rng) & mask_of(low) : at & mask_of(low);
            const uint64_t hi = low >= 64 ? 0 : top << low;
            k[j] = ((hi | lowbits) & m) | (tu_next(&rng) & ~m);
            ix[j] = (uint32_t)j;
        }
        i += g;
        top += 1 + tu_below(&rng, 2);
    }
    memcpy(rk, k, n * sizeof *k);
    memcpy(ri, ix, n * sizeof *ix);
    sort_radix_pairs(rk, ri, n, bits, tk, ti, 1);
    sort_radix_pairs_grouped(k, ix, n, bits, tk, ti, threads);
    TEST_CHECK(memcmp(rk, k, n * sizeof *k) == 0 && memcmp(ri, ix, n * sizeof *ix) == 0,
               "%s (n=%zu bits=%d low=%d threads=%d): not sort_radix_pairs's order", what, n,
               bits, low, threads);
    free(k); free(tk); free(rk); free(ix); free(ti); free(ri);
}

static void test_grouped_sort_equals_the_full_sort(void)
{
    for (int t = 1; t <= 3; t++) {
        check_grouped(200000, 63, 20, 64, t, 31 + t, "small groups");
        check_grouped(300000, 63, 40, 120000, t, 41 + t, "big and small groups");
        check_grouped(100000, 45, 45, 100000, t, 51 + t, "descents at the top bit");
        check_grouped(70000, 64, 64, 70000, t, 61 + t, "shuffled");
        check_grouped(50000, 30, 10, 1, t, 71 + t, "sorted (groups of one)");
        check_grouped(5, 63, 20, 3, t, 81 + t, "five keys");
    }
}

int main(void)
{
    TU_RUN(test_radix_equals_stable_reference_at_boundary_sizes);
    TU_RUN(test_radix_equals_reference_on_few_distinct_values_and_skewed_keys);
    TU_RUN(test_radix_sorts_one_million_keys_like_the_reference);
    TU_RUN(test_radix_is_stable_on_equal_keys);
    TU_RUN(test_radix_output_is_identical_for_threads_1_to_4);
    TU_RUN(test_radix_ignores_zero_bits_and_clamps_large_key_bits);
    TU_RUN(test_grouped_sort_equals_the_full_sort);
    return tu_finish();
}
