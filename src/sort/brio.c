/* brio.c -- the biased randomized insertion order (BRIO, Amenta-Choi-Rote) on the Moore curve.
 *
 * Shuffle, cut into rounds of geometrically growing size, sort each round along the Moore
 * curve of the set's bounding box (seed paper section 3; HXT's computePasses), then sort again,
 * on its own box, every long run of points that share a Moore cell.  Early rounds are random
 * samples of the whole set, so the triangulation they build is well shaped; inside a round the
 * curve order keeps consecutive insertions close, so the walk is short -- also when most
 * points sit in a few cells of the box (one point far away, clusters, heavy tails), which the
 * refinement sorts as finely as a uniform set.  One box and one key length for every round let
 * the parallel kernel colour its vertices with these keys (sort_brio_keys).
 *
 * The definition (sort.h) is "sort by hash, cut, Moore-sort each round stably, refine long
 * runs".  Done literally, each round would read its points in random order (two cache misses
 * per point); instead every step here reads the points in input order:
 *   1. the hashes of rank round_end[r] - 1 (the round thresholds) are found by selection: a
 *      histogram of the top 12 hash bits, then an exact sort of the few buckets that hold a
 *      threshold rank;
 *   2. a point's round is the first r whose threshold is >= its hash (hashes are distinct:
 *      the hash is a bijection of the id, and ids are distinct), which is exactly its round
 *      in the hash order; then the bounding box of all the points (sort_bbox);
 *   3. key = round << S | Moore key on the box (S = 3 * bits), and one stable radix sort of all
 *      (key, id) pairs puts the rounds in order, each in Moore order;
 *   4. equal keys (points of one Moore cell) are then put in hash order: a run of equal keys
 *      is sorted by hash, which is the tie order the definition gives; a run longer than
 *      BRIO_REFINE_MIN is then refined: first by the 21-bit keys on the same box (the keys
 *      continued, refine_global), then the runs still equal on their own boxes (refine_run).
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

#include "../base/base.h"
#include "sort_internal.h"

#define BRIO_MAX_ROUNDS 64
#define BRIO_PARALLEL_MIN 8192
#define BRIO_SELECT_BITS 12
#define BRIO_SELECT_SIZE (1u << BRIO_SELECT_BITS)
#define BRIO_REFINE_MIN 32   /* longer runs of equal keys are sorted on their own box */
#define BRIO_CROWD_MIN 4096   /* rounds this large count for sort_brio_keys' crowd_out */
#define BRIO_REFINE_DEPTH 32 /* levels of that (each shrinks the box by 2^5 or more per axis) */
#define BRIO_FINE_BITS 21    /* the refinement's first level, and the keys handed out: the
                                kernel's (slices.h KPAR_KEY_BITS) */

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

/* Round of each point (round[i]), in input order. */
static void rounds_of(const uint64_t *h, size_t n, const uint64_t *thr, int rounds,
                      uint8_t *round, int threads)
{
    const int nt = (threads > 1 && n >= BRIO_PARALLEL_MIN) ? threads : 1;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++) {
        int r = rounds - 1;
        while (r > 0 && h[i] <= thr[r - 1])
            r--;
        round[i] = (uint8_t)r;
    }
}

/* ids[0..n) in hash order (the definition's tie order): hk and kscr, ti scratch of n entries.
 * Hashes are distinct (a bijection of the id), so the order is a function of the set. */
static void hash_order(uint32_t *ids, size_t n, uint64_t salt, uint64_t *hk, uint64_t *kscr,
                       uint32_t *ti, int threads)
{
    if (n <= BRIO_REFINE_MIN) {  /* a leaf: insertion sort */
        for (size_t u = 0; u < n; u++) {
            const uint64_t h = sort_hash64((uint64_t)ids[u] + salt);
            const uint32_t id = ids[u];
            size_t v = u;
            for (; v > 0 && hk[v - 1] > h; v--) {
                hk[v] = hk[v - 1];
                ids[v] = ids[v - 1];
            }
            hk[v] = h;
            ids[v] = id;
        }
        return;
    }
    for (size_t u = 0; u < n; u++) hk[u] = sort_hash64((uint64_t)ids[u] + salt);
    sort_radix_pairs(hk, ids, n, 64, kscr, ti, threads);
}

/* Refinement of a run of n > BRIO_REFINE_MIN points with equal keys: stable sort by the Moore
 * key on the run's own box with sort_brio_bits(n) bits, then the same for every sub-run of
 * equal keys longer than BRIO_REFINE_MIN, down to depth BRIO_REFINE_DEPTH; every run of equal
 * keys that is not refined further (a leaf, a run at the last depth, a run whose points all
 * coincide) is then put in hash order.  This is the order sort.h defines (the run in hash
 * order, then stable sorts by the finer keys: ties in hash order), reached without sorting the
 * whole run by hash first: the run's ids come in the order of the sort before, close to input
 * order, so the keys' reads of their coordinates go forward through memory, where in hash
 * order each was a cache miss (NOTES.md E176).  run_box: NULL, or the run's sort_bbox when the
 * caller has it (fine_keys_help).  kscr, tk, ti: scratch of n entries.  The
 * run's box shrinks by 2^bits >= 32 per axis at each level (a sub-run lies in one cell of its
 * parent's box), so the depth bounds both the recursion and the work: at most
 * BRIO_REFINE_DEPTH keys and sorts per point. */
static size_t order_equal_runs(const double *xyz, size_t stride, uint32_t *ids, size_t n,
                               int depth, uint64_t *keys, uint64_t *tk, uint32_t *ti,
                               uint64_t salt, int threads);

static void refine_run(const double *xyz, size_t stride, uint32_t *ids, size_t n, int depth,
                       const double *run_box, uint64_t *kscr, uint64_t *tk, uint32_t *ti,
                       uint64_t salt, int threads)
{
    double box[6];
    if (run_box)  /* the caller's sort_bbox of the same points */
        memcpy(box, run_box, sizeof box);
    else
        sort_bbox(xyz, stride, ids, n, box, threads);
    if (box[0] == box[3] && box[1] == box[4] && box[2] == box[5]) {
        hash_order(ids, n, salt, tk, kscr, ti, threads);
        return;
    }
    const int bits = sort_brio_bits(n);
    sort_moore_keys_ids(xyz, stride, ids, n, box, bits, kscr, threads);
    sort_radix_pairs(kscr, ids, n, 3 * bits, tk, ti, threads);
    order_equal_runs(xyz, stride, ids, n, depth + 1, kscr, tk, ti, salt, threads);
}

/* Every maximal run of equal keys[0..n) (sorted) that is longer than BRIO_REFINE_MIN refined
 * at `depth` (refine_run, while depth <= BRIO_REFINE_DEPTH), every other run of two or more
 * put in hash order; a run is the levels' scratch and gets its key back.  Returns the longest
 * run. */
static size_t order_equal_runs(const double *xyz, size_t stride, uint32_t *ids, size_t n,
                               int depth, uint64_t *keys, uint64_t *tk, uint32_t *ti,
                               uint64_t salt, int threads)
{
    size_t longest = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && keys[j] == keys[i])
            j++;
        if (j - i > longest)
            longest = j - i;
        if (j - i > 1) {
            const uint64_t key = keys[i];
            if (j - i > BRIO_REFINE_MIN && depth <= BRIO_REFINE_DEPTH)
                refine_run(xyz, stride, ids + i, j - i, depth, NULL, keys + i, tk + i, ti + i,
                           salt, threads);
            else
                hash_order(ids + i, j - i, salt, tk + i, keys + i, ti + i, threads);
            for (size_t u = i; u < j; u++)
                keys[u] = key;
        }
        i = j;
    }
    return longest;
}

/* Whether the fine keys (BRIO_FINE_BITS bits per axis on the set's box `box`) order the run
 * ids[0..n) about as finely as its own box would: its box spans at least 2^(b-1) fine cells
 * on some axis, b = sort_brio_bits(n) the bits refine_run would take there.  Not so for the
 * unit cube next to a point at 10^6 (2 fine cells an axis): there the fine keys would be
 * computed and sorted for nothing, and the run is refined on its own box at once. */
static int fine_keys_help(const double *xyz, size_t stride, const uint32_t *ids, size_t n,
                          const double box[6], double rb[6], int threads)
{
    sort_bbox(xyz, stride, ids, n, rb, threads);  /* rb: the run's box, for refine_run too */
    const double want = ldexp(1.0, sort_brio_bits(n) - 1 - BRIO_FINE_BITS);
    for (int a = 0; a < 3; a++)  /* (exact min/max and IEEE operations: deterministic) */
        if (rb[a + 3] - rb[a] >= want * (box[a + 3] - box[a]) && rb[a + 3] > rb[a])
            return 1;
    return 0;
}

/* The first level of a run's refinement (n > BRIO_REFINE_MIN points with equal keys on the
 * set's box `box` with fewer than BRIO_FINE_BITS bits, fine_keys_help): stable sort by the
 * Moore keys on the same box with BRIO_FINE_BITS bits, which continue the run's key (the
 * prefix property, sort.h), then refine_run from depth 2 for every run of equal such keys
 * longer than BRIO_REFINE_MIN, hash order for the shorter ones.  On return fine[i] is the fine key of the
 * point now at ids[i] (fine[] does not decrease), and the result is the longest run of equal
 * fine keys.  A dense cluster is thus in the order of the curve the kernel cuts its slices on
 * (its keys are these, NOTES.md E257); refined on the run's own box at once, it followed
 * another curve, and the kernel keyed every point again and sorted the cluster's points in
 * each round's first pass.  tk, ti: scratch of n entries; a run of equal fine keys is its own
 * scratch for the levels below, and gets its key back. */
static size_t refine_global(const double *xyz, size_t stride, uint32_t *ids, size_t n,
                            const double box[6], int kbits, uint64_t *fine, uint64_t *tk,
                            uint32_t *ti, uint64_t salt, int threads)
{
    sort_moore_keys_ids(xyz, stride, ids, n, box, BRIO_FINE_BITS, fine, threads);
    /* the bits above these are the run's key, the same for all */
    sort_radix_pairs(fine, ids, n, 3 * (BRIO_FINE_BITS - kbits), tk, ti, threads);
    return order_equal_runs(xyz, stride, ids, n, 2, fine, tk, ti, salt, threads);
}

gtet_status sort_brio(const double *xyz, size_t stride, uint32_t *ids, size_t n, uint64_t seed,
                      size_t first, double ratio, size_t round_end[64], int *num_rounds,
                      int threads)
{
    return sort_brio_keys(xyz, stride, ids, n, seed, first, ratio, round_end, num_rounds,
                          threads, NULL, NULL, NULL, NULL);
}

/* Step 4 of sort_brio_keys: runs of equal keys into hash order, the long ones refined
 * (refine_global; keys[i..j) is scratch once the run is found), and every key rewritten as a
 * fine key (BRIO_FINE_BITS bits per axis, no round): a refined run's points get their own,
 * the others their cell's key shifted up (the first fine key in the cell, by the prefix
 * property), so the keys do not decrease within a round.  *refined: the points in refined
 * runs; *crowd: the largest share of a round (of at least BRIO_CROWD_MIN points) that one
 * fine key holds. */
static void order_runs(const double *xyz, size_t stride, uint32_t *ids, size_t n, uint64_t *keys,
                       uint64_t *tk, uint32_t *ti, int kbits, const double box[6],
                       const size_t *end, uint64_t salt, int threads, size_t *refined_out,
                       double *crowd_out)
{
    size_t refined = 0;
    double crowd = 0.0;
    const int up = 3 * (BRIO_FINE_BITS - kbits);
    const uint64_t cell = ((uint64_t)1 << (3 * kbits)) - 1;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && keys[j] == keys[i])
            j++;
        const int r = (int)(keys[i] >> (3 * kbits));
        const size_t rsize = end[r] - (r ? end[r - 1] : 0);
        size_t same = j - i;  /* the longest run of equal fine keys */
        const uint64_t fine = (keys[i] & cell) << up;
        double rb[6];  /* the run's box, when fine_keys_help computed it */
        const int have_rb = j - i > BRIO_REFINE_MIN && up > 0;
        if (have_rb && fine_keys_help(xyz, stride, ids + i, j - i, box, rb, threads)) {
            /* ends in hash order within its finer keys */
            same = refine_global(xyz, stride, ids + i, j - i, box, kbits, keys + i, tk + i,
                                 ti + i, salt, threads);
            refined += j - i;
        } else {
            if (j - i > BRIO_REFINE_MIN) {
                refine_run(xyz, stride, ids + i, j - i, 1, have_rb ? rb : NULL, keys + i,
                           tk + i, ti + i, salt, threads);
                refined += j - i;
            } else if (j - i > 1) {
                hash_order(ids + i, j - i, salt, tk + i, keys + i, ti + i, threads);
            }
            for (size_t u = i; u < j; u++)
                keys[u] = fine;
        }
        if (rsize >= BRIO_CROWD_MIN && (double)same / (double)rsize > crowd)
            crowd = (double)same / (double)rsize;
        i = j;
    }
    *refined_out = refined;
    *crowd_out = crowd;
}

gtet_status sort_brio_keys(const double *xyz, size_t stride, uint32_t *ids, size_t n,
                           uint64_t seed, size_t first, double ratio, size_t round_end[64],
                           int *num_rounds, int threads, uint64_t **keys_out, int *key_bits_out,
                           size_t *refined_out, double *crowd_out)
{
    if (crowd_out)
        *crowd_out = 0.0;
    if (keys_out)
        *keys_out = NULL;
    if (refined_out)
        *refined_out = 0;
    if (key_bits_out)
        *key_bits_out = BRIO_FINE_BITS;
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
    uint64_t *keys = base_alloc_big(n * sizeof *keys);
    uint64_t *tk = base_alloc_big(n * sizeof *tk);
    uint32_t *ti = base_alloc_big(n * sizeof *ti);
    uint8_t *round = base_alloc_big(n);
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

    /* 2. rounds and the box; 3. keys and one stable sort */
    double box[6];
    const int kbits = sort_brio_bits(n);
    rounds_of(tk, n, thr, rounds, round, threads);
    sort_bbox(xyz, stride, ids, n, box, threads);
    int rbits = 0;
    while ((1 << rbits) < rounds)
        rbits++;
    sort_moore_keys_rounds(xyz, stride, ids, n, round, rounds, box, kbits, 3 * kbits, keys,
                           threads);
    sort_radix_pairs(keys, ids, n, 3 * kbits + rbits, tk, ti, threads);

    /* 4. */
    size_t refined = 0;
    double crowd = 0.0;
    order_runs(xyz, stride, ids, n, keys, tk, ti, kbits, box, end, salt, threads, &refined,
               &crowd);
    if (refined_out)
        *refined_out = refined;
    if (crowd_out)
        *crowd_out = crowd;
    for (int r = 0; r < rounds; r++)
        round_end[r] = end[r];
    *num_rounds = rounds;
    st = GTET_OK;
    if (keys_out) {
        *keys_out = keys;
        keys = NULL;
    }
out:
    free(keys);
    free(tk);
    free(ti);
    free(round);
    return st;
}
