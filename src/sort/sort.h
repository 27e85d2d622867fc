/* sort.h -- internal interface of spatial sorting (prefix sort_).
 *
 * Moore-curve keys (the looping Hilbert curve of the seed paper, Fig. 1b) on a bounding box,
 * a parallel LSD radix sort of (key, index) pairs using only the bits needed, and the BRIO
 * insertion order built from them.  Deterministic: the output depends on the inputs and the
 * seed only, never on the thread count.
 */
#ifndef GTET_SORT_H
#define GTET_SORT_H

#include <stddef.h>
#include <stdint.h>
#include "gigatet.h"

/* Moore key of each point on a grid of 2^bits cells per axis over bbox
 * {xmin,ymin,zmin,xmax,ymax,zmax} (3*bits <= 63).  Point i is at xyz + i*stride (doubles).
 * Points outside the box are clamped.  threads <= 1: serial.
 * Keys are a bijection from the 2^(3 bits) cells onto [0, 2^(3 bits)); consecutive keys are
 * face-adjacent cells, the last cell is adjacent to the first (the loop), and the key with
 * `bits` is the key with `bits + 1` shifted right by 3 (prefix property).  A NaN coordinate
 * counts as the low end of its axis.  bits <= 0: every key is 0; bits > 21 is taken as 21. */
void sort_moore_keys(const double *xyz, size_t stride, size_t n, const double bbox[6], int bits,
                     uint64_t *keys, int threads);

/* As sort_moore_keys for the points ids[0..n): keys[i] is the key of the point at
 * xyz + ids[i]*stride. */
void sort_moore_keys_ids(const double *xyz, size_t stride, const uint32_t *ids, size_t n,
                         const double bbox[6], int bits, uint64_t *keys, int threads);

/* The bounding box {xmin,ymin,zmin,xmax,ymax,zmax} of the points ids[0..n) (ids NULL:
 * points 0..n-1), with -0.0 written as +0.0 so that it does not depend on the thread count.
 * n == 0 gives all zeros.  NaN coordinates are ignored. */
void sort_bbox(const double *xyz, size_t stride, const uint32_t *ids, size_t n, double bbox[6],
               int threads);

/* The "bounding box expansion" of seed paper section 4.2 (a shifted curve for a conflict pass):
 * out is the pass-th enlarged and shifted box of bbox.  Only the tests call it: the kernel's
 * passes shift their boxes with parallel.c's pass_box.
 * pass <= 0 or !(factor > 1): out = bbox.  Otherwise, on each axis a of extent E (the largest
 * extent of the box when this axis is flat), with u in [0,1) a hash of (seed, pass, a):
 *   out_lo = lo - u (factor-1) E,   out_hi = hi + (1-u) (factor-1) E,
 * so the box grows to factor times its extent (a flat axis to (factor-1) E) and contains
 * bbox (enforced exactly; the result is clamped to +-DBL_MAX; factor is capped at 2^20);
 * its centre, hence the curve's partition planes, moves by (1/2 - u)(factor-1) E.
 * Deterministic: IEEE operations only.  bbox and out may be the same array. */
void sort_bbox_expand(const double bbox[6], double factor, uint64_t seed, int pass,
                      double out[6]);

/* Stable sort of idx[0..n) by keys (keys permuted alongside), looking only at the low
 * key_bits bits.  tmp_keys / tmp_idx are caller-provided scratch of n entries each.
 * threads <= 1: serial.  The output is the unique stable order, so it never depends on the
 * thread count.  key_bits <= 0: nothing to do; key_bits > 64 is taken as 64.  The parallel
 * path uses at most 256 threads and needs 16 KiB of histograms per thread: if that
 * allocation fails it runs serially. */
void sort_radix_pairs(uint64_t *keys, uint32_t *idx, size_t n, int key_bits,
                      uint64_t *tmp_keys, uint32_t *tmp_idx, int threads);

/* The same result as sort_radix_pairs (the unique stable order on the low key_bits bits), for
 * keys that are sorted but for descents confined to groups: with L the highest bit in which
 * the two keys of any descent (a key greater than the next) differ, the keys' bits above L are
 * then already in order, and only each run of equal such bits that holds a descent is sorted,
 * on bits 0..L.  A BRIO round whose crowded cells were refined on their own boxes is in key
 * order but inside those cells (the kernel's first pass on a dense cluster, NOTES.md E101).
 * Runs shorter than 32768 keys are shared out between the threads, longer ones sorted one
 * after another with all of them. */
void sort_radix_pairs_grouped(uint64_t *keys, uint32_t *idx, size_t n, int key_bits,
                              uint64_t *tmp_keys, uint32_t *tmp_idx, int threads);

/* The BRIO order of points xyz[i*stride] for the listed point ids ids[0..n):
 * shuffle by a hash of (id, seed), cut into rounds (the first of at most `first` points, each
 * next about `ratio` times larger), and sort each round on the Moore curve of the bounding box
 * of all n points, refining the cells that hold many points.  On return ids[] holds the
 * insertion order and round_end[r] (r < *num_rounds <= 64) the exclusive end of round r.
 * Returns GTET_OK or GTET_ERR_OUT_OF_MEMORY.
 * Precisely: the shuffle sorts ids by sort_hash64(id + sort_hash64(seed)) (a bijection of the
 * id, so no ties among distinct ids: the order depends on the set of ids, not on their order
 * in ids[]; ids must be distinct -- with repeated ids the output is still a permutation of
 * ids[], but equal ids stay in one round, so round sizes may differ from the rule below).  Round
 * ends: round_end[R-1] = n and, while round_end[r] > first,
 *   round_end[r-1] = min(max(floor(round_end[r] / ratio), 1), round_end[r] - 1);
 * if that would make more than 64 rounds, the smallest ones are merged into the first (which
 * then holds more than `first` points).  Round r = [round_end[r-1], round_end[r]) is stably
 * sorted by sort_moore_keys_ids with sort_bbox of all n points and sort_brio_bits(n) bits per
 * axis (equal keys thus stay in hash order).  Refinement: every maximal run of more than 32
 * consecutive points of a round with equal keys is stably sorted by sort_moore_keys_ids on
 * the same box with 21 bits per axis (the fine keys), when sort_brio_bits(n) is below 21 and
 * the run's sort_bbox is, on some axis, at least 2^(sort_brio_bits(run length) - 22) times as
 * wide as the set's box and not flat; then every maximal run of more than 32 points with
 * equal fine keys (or, without that level, the run itself), unless its points all coincide,
 * is stably sorted by sort_moore_keys_ids on sort_bbox of the run's points with
 * sort_brio_bits(run length) bits, and so on for the runs of equal keys that this makes, to 32
 * levels in all.  (Without it, one point far away puts every other point into one Moore cell,
 * whose points would then come in random order: NOTES.md E8.  The fine keys first: a dense
 * cluster is then in the order of the keys the kernel cuts its slices on, E257.)
 * Memory: 21 bytes per point, freed on return.
 * Also: GTET_ERR_ARGUMENT when n > 0 and a pointer is NULL, first == 0, !(ratio > 1),
 * or n > 2^32.  n == 0 gives *num_rounds = 0. */
gtet_status sort_brio(const double *xyz, size_t stride, uint32_t *ids, size_t n, uint64_t seed,
                      size_t first, double ratio, size_t round_end[64], int *num_rounds,
                      int threads);

/* sort_brio, and its keys.  When keys_out is not NULL and the result is GTET_OK,
 * *keys_out is a malloc'ed array of n keys (the caller frees it; NULL otherwise), Moore keys on
 * the box of all n points with *key_bits_out = 21 bits per axis: (*keys_out)[i] is the fine key
 * of the point ids[i] (after sorting) when its run was refined by the fine keys, else its key
 * with b = sort_brio_bits(n) bits shifted up by 3 (21 - b) bits (the first fine key of its
 * cell, by the prefix property); so the keys do not decrease along each round, and two points
 * of different cells compare as their cells do.  The memory is sort_brio's own key array (8 bytes per point),
 * kept instead of freed.  When not NULL: *refined_out is the number of points in runs that
 * were refined -- 0 when every Moore cell of the box held at most 32 points of a round, i.e.
 * when the keys with b bits alone order the set finely; *crowd_out is the largest share of a
 * round's points that one key of *keys_out holds, over the rounds of at least 4096 points (0
 * when there is none) -- how finely the keys can cut a round into slices: a share above 1/k
 * leaves one of k slices more than its part. */
gtet_status sort_brio_keys(const double *xyz, size_t stride, uint32_t *ids, size_t n,
                           uint64_t seed, size_t first, double ratio, size_t round_end[64],
                           int *num_rounds, int threads, uint64_t **keys_out,
                           int *key_bits_out, size_t *refined_out, double *crowd_out);

/* Bits per axis of the Moore keys of a BRIO round of m points:
 * ceil(log2(m) / 3) + 3, between 1 and 21 (about 64 to 512 cells per point: enough to order
 * the round, few enough that the radix sort makes ceil(3 bits / 11) passes). */
int sort_brio_bits(size_t m);

/* A bijective 64-bit mixer (the splitmix64 finaliser), the library's reproducible
 * hash for shuffles and shifts. */
static inline uint64_t sort_hash64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#endif
