/* brio.c -- the biased randomized insertion order (BRIO, Amenta-Choi-Rote) on the Moore curve.
 *
 * Shuffle, cut into rounds of geometrically growing size, sort each round along the Moore
 * curve of its own bounding box (seed paper section 3; HXT's computePasses).  Early rounds
 * are random samples of the whole set, so the triangulation they build is well shaped; inside
 * a round the curve order keeps consecutive insertions close, so the walk is short.
 *
 * Why it is deterministic: the shuffle key of a point is a bijective hash of its id and the
 * seed (no ties, so the shuffled order depends on the set of ids, not on their order or on
 * threads); the round ends are a function of n, first and ratio in IEEE arithmetic; each
 * round's bounding box is exact (min/max) with -0.0 normalised; its keys depend on the box and
 * the point only; and the radix sort is stable, hence its output is unique.
 */
#include "sort.h"

#include <math.h>
#include <stdlib.h>

#define BRIO_MAX_ROUNDS 64
#define BRIO_PARALLEL_MIN 8192

int sort_brio_bits(size_t m)
{
    int l = 0;  /* ceil(log2(m)) */
    while (l < 64 && ((size_t)1 << l) < m)
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
        double q = floor((double)e / ratio);
        size_t nx = q < 1.0 ? 1 : q >= (double)e ? e - 1 : (size_t)q;
        if (nx > e - 1)
            nx = e - 1;
        down[r++] = nx;
    }
    for (int i = 0; i < r; i++)
        round_end[i] = down[r - 1 - i];
    return r;
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

    uint64_t *keys = malloc(n * sizeof *keys);
    uint64_t *tk = malloc(n * sizeof *tk);
    uint32_t *ti = malloc(n * sizeof *ti);
    if (!keys || !tk || !ti) {
        free(keys);
        free(tk);
        free(ti);
        return GTET_ERR_OUT_OF_MEMORY;
    }

    /* shuffle: sort by a bijective 64-bit hash of the id */
    const uint64_t salt = sort_hash64(seed);
    const int nt = (threads > 1 && n >= BRIO_PARALLEL_MIN) ? threads : 1;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++)
        keys[i] = sort_hash64((uint64_t)ids[i] + salt);
    sort_radix_pairs(keys, ids, n, 64, tk, ti, threads);

    /* rounds, each on the Moore curve of its own bounding box */
    const int rounds = brio_rounds(n, first, ratio, round_end);
    size_t lo = 0;
    for (int r = 0; r < rounds; r++) {
        const size_t m = round_end[r] - lo;
        double box[6];
        const int bits = sort_brio_bits(m);
        sort_bbox(xyz, stride, ids + lo, m, box, threads);
        sort_moore_keys_ids(xyz, stride, ids + lo, m, box, bits, keys + lo, threads);
        sort_radix_pairs(keys + lo, ids + lo, m, 3 * bits, tk, ti, threads);
        lo = round_end[r];
    }
    *num_rounds = rounds;
    free(keys);
    free(tk);
    free(ti);
    return GTET_OK;
}
