/* brio.c -- the biased randomized insertion order (BRIO, Amenta-Choi-Rote) on the Moore curve.
 *
 * Shuffle, cut into rounds of geometrically growing size, sort each round along the Moore
 * curve of its own bounding box (seed paper section 3; HXT's computePasses).  Early rounds
 * are random samples of the whole set, so the triangulation they build is well shaped; inside
 * a round the curve order keeps consecutive insertions close, so the walk is short.
 *
 * The definition (sort.h) is "sort by hash, cut, Moore-sort each round stably".  Done
 * literally, each round would read its points in random order (two cache misses per point);
 * instead every step here reads the points in input order:
 *   1. the hashes of rank round_end[r] - 1 (the round thresholds) are found by selection: a
 *      histogram of the top 12 hash bits, then an exact sort of the few buckets that hold a
 *      threshold rank;
 *   2. a point's round is the first r whose threshold is >= its hash (hashes are distinct:
 *      the hash is a bijection of the id, and ids are distinct), which is exactly its round
 *      in the hash order; the rounds' bounding boxes are accumulated in the same pass;
 *   3. key = round << S | Moore key on the round's box (S = 3 * the largest bits), and one
 *      stable radix sort of all (key, id) pairs puts the rounds in order, each in Moore
 *      order;
 *   4. equal keys (points of one Moore cell) are then put in hash order: a run of equal keys
 *      is sorted by hash, which is the tie order the definition gives.
 *
 * Why it is deterministic: the hash depends on (id, seed) only; thresholds, rounds, boxes
 * (exact min/max, -0.0 normalised) and keys depend on the data only; stable sorts have unique
 * outputs.  Nothing depends on the thread count or on the order of ids[].
 */
#include "sort.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sort_internal.h"

#define BRIO_MAX_ROUNDS 64
#define BRIO_PARALLEL_MIN 8192
#define BRIO_SELECT_BITS 12
#define BRIO_SELECT_SIZE (1u << BRIO_SELECT_BITS)

int sort_brio_bits(size_t m)
{
    int l = 0;  /* ceil(log2(m)) */
    while (l < 63 && ((size_t)1 << l) < m)
        l++;
    int bits = (l + 2) / 3 + 3;
    return bits > 21 ? 21 : bits;
}

/* Round ends, see sort.h; returns the number of rounds (n >= 1). */
static int brio_rounds(size_t n, size_t first, double ratio, size_t round_end[64])
{
    size_t down[BRIO_MAX_ROUNDS];
    int r = 0;
    down[r++] = n;
    while (down[r - 1] > first && r < BRIO_MAX_ROUNDS) {
        const size_t e = down[r - 1];
        const double q = floor((double)e / ratio);
        size_t nx = q < 1.0 ? 1 : q >= (double)e ? e - 1 : (size_t)q;
        if (nx > e - 1)
            nx = e - 1;
        down[r++] = nx;
    }
    for (int i = 0; i < r; i++)
        round_end[i] = down[r - 1 - i];
    return r;
}

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* thr[j] = the value of rank rank[j] (0-based, increasing) among h[0..n), j < k.
 * Returns GTET_OK or GTET_ERR_OUT_OF_MEMORY. */
static gtet_status select_ranks(const uint64_t *h, size_t n, const size_t *rank, int k,
                                uint64_t *thr, int threads)
{
    if (k <= 0)
        return GTET_OK;
    size_t *cnt = calloc(BRIO_SELECT_SIZE + 1, sizeof *cnt);
    if (!cnt)
        return GTET_ERR_OUT_OF_MEMORY;
    const int shift = 64 - BRIO_SELECT_BITS;
    const int nt = (threads > 1 && n >= BRIO_PARALLEL_MIN) ? threads : 1;
#pragma omp parallel num_threads(nt) if (nt > 1)
    {
        size_t local[BRIO_SELECT_SIZE];
        memset(local, 0, sizeof local);
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++)
            local[h[i] >> shift]++;
#pragma omp critical(gtet_brio_select)
        for (size_t b = 0; b < BRIO_SELECT_SIZE; b++)
            cnt[b] += local[b];
    }
    /* cnt -> bucket starts; mark the buckets holding a wanted rank, count their members */
    unsigned char mark[BRIO_SELECT_SIZE];
    memset(mark, 0, sizeof mark);
    size_t sum = 0;
    for (size_t b = 0; b <= BRIO_SELECT_SIZE; b++) {
        const size_t c = cnt[b];
        cnt[b] = sum;
        sum += c;
    }
    size_t ncand = 0;
    for (int j = 0; j < k; j++) {
        size_t b = 0;
        while (cnt[b + 1] <= rank[j])  /* the bucket b with start <= rank < next start */
            b++;
        if (!mark[b])
            ncand += cnt[b + 1] - cnt[b];
        mark[b] = 1;
    }
    uint64_t *cand = malloc((ncand ? ncand : 1) * sizeof *cand);
    if (!cand) {
        free(cnt);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    size_t c = 0;
    for (size_t i = 0; i < n; i++)
        if (mark[h[i] >> shift])
            cand[c++] = h[i];
    qsort(cand, c, sizeof *cand, cmp_u64);
    /* rank r in bucket b is candidate (members of marked buckets before b) + r - start(b) */
    for (int j = 0; j < k; j++) {
        size_t before = 0, b = 0;
        for (; cnt[b + 1] <= rank[j]; b++)
            if (mark[b])
                before += cnt[b + 1] - cnt[b];
        thr[j] = cand[before + rank[j] - cnt[b]];
    }
    free(cand);
    free(cnt);
    return GTET_OK;
}

/* Round of each point (round[i]) and the rounds' bounding boxes, in input order. */
static void rounds_and_boxes(const double *xyz, size_t stride, const uint32_t *ids,
                             const uint64_t *h, size_t n, const uint64_t *thr, int rounds,
                             uint8_t *round, double (*box)[6], int threads)
{
    for (int r = 0; r < rounds; r++)
        for (int a = 0; a < 3; a++) {
            box[r][a] = INFINITY;
            box[r][a + 3] = -INFINITY;
        }
    const int nt = (threads > 1 && n >= BRIO_PARALLEL_MIN) ? threads : 1;
#pragma omp parallel num_threads(nt) if (nt > 1)
    {
        double lb[BRIO_MAX_ROUNDS][6];
        for (int r = 0; r < rounds; r++)
            for (int a = 0; a < 3; a++) {
                lb[r][a] = INFINITY;
                lb[r][a + 3] = -INFINITY;
            }
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++) {
            int r = rounds - 1;
            while (r > 0 && h[i] <= thr[r - 1])
                r--;
            round[i] = (uint8_t)r;
            const double *p = xyz + (size_t)ids[i] * stride;
            for (int a = 0; a < 3; a++) {
                if (p[a] < lb[r][a]) lb[r][a] = p[a];
                if (p[a] > lb[r][a + 3]) lb[r][a + 3] = p[a];
            }
        }
#pragma omp critical(gtet_brio_boxes)
        for (int r = 0; r < rounds; r++)
            for (int a = 0; a < 3; a++) {
                if (lb[r][a] < box[r][a]) box[r][a] = lb[r][a];
                if (lb[r][a + 3] > box[r][a + 3]) box[r][a + 3] = lb[r][a + 3];
            }
    }
    /* as sort_bbox: -0.0 -> +0.0 (min/max are exact, only a zero's sign could vary) */
    for (int r = 0; r < rounds; r++)
        for (int a = 0; a < 3; a++) {
            const int empty = !(box[r][a] <= box[r][a + 3]);
            box[r][a] = empty ? 0.0 : box[r][a] + 0.0;
            box[r][a + 3] = empty ? 0.0 : box[r][a + 3] + 0.0;
        }
}

gtet_status sort_brio(const double *xyz, size_t stride, uint32_t *ids, size_t n, uint64_t seed,
                      size_t first, double ratio, size_t round_end[64], int *num_rounds,
                      int threads)
{
    if (!num_rounds)
        return GTET_ERR_ARGUMENT;
    *num_rounds = 0;
    if (n == 0)
        return GTET_OK;
    if (!xyz || !ids || !round_end || first == 0 || !(ratio > 1.0) ||
        n > (size_t)UINT32_MAX + 1u)
        return GTET_ERR_ARGUMENT;

    size_t end[BRIO_MAX_ROUNDS];
    const int rounds = brio_rounds(n, first, ratio, end);
    uint64_t *keys = malloc(n * sizeof *keys);
    uint64_t *tk = malloc(n * sizeof *tk);
    uint32_t *ti = malloc(n * sizeof *ti);
    uint8_t *round = malloc(n);
    gtet_status st = GTET_ERR_OUT_OF_MEMORY;
    if (!keys || !tk || !ti || !round)
        goto out;

    /* 1. hashes (in tk) and the thresholds of the rounds */
    const uint64_t salt = sort_hash64(seed);
    const int nt = (threads > 1 && n >= BRIO_PARALLEL_MIN) ? threads : 1;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++)
        tk[i] = sort_hash64((uint64_t)ids[i] + salt);
    size_t rank[BRIO_MAX_ROUNDS];
    uint64_t thr[BRIO_MAX_ROUNDS];
    for (int r = 0; r + 1 < rounds; r++)
        rank[r] = end[r] - 1;
    st = select_ranks(tk, n, rank, rounds - 1, thr, threads);
    if (st != GTET_OK)
        goto out;

    /* 2. rounds and their boxes; 3. keys and one stable sort */
    double box[BRIO_MAX_ROUNDS][6];
    int bits[BRIO_MAX_ROUNDS], maxbits = 1;
    rounds_and_boxes(xyz, stride, ids, tk, n, thr, rounds, round, box, threads);
    for (int r = 0; r < rounds; r++) {
        bits[r] = sort_brio_bits(end[r] - (r ? end[r - 1] : 0));
        if (bits[r] > maxbits)
            maxbits = bits[r];
    }
    int rbits = 0;
    while ((1 << rbits) < rounds)
        rbits++;
    sort_moore_keys_rounds(xyz, stride, ids, n, round, rounds, (const double (*)[6])box, bits,
                           3 * maxbits, keys, threads);
    sort_radix_pairs(keys, ids, n, 3 * maxbits + rbits, tk, ti, threads);

    /* 4. runs of equal keys into hash order (keys[i..j) is free once the run is found) */
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && keys[j] == keys[i])
            j++;
        if (j - i > 1) {
            for (size_t u = i; u < j; u++)
                tk[u] = sort_hash64((uint64_t)ids[u] + salt);
            sort_radix_pairs(tk + i, ids + i, j - i, 64, keys + i, ti + i, threads);
        }
        i = j;
    }
    for (int r = 0; r < rounds; r++)
        round_end[r] = end[r];
    *num_rounds = rounds;
    st = GTET_OK;
out:
    free(keys);
    free(tk);
    free(ti);
    free(round);
    return st;
}
