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
#include "../gigatet.h"

/* Moore key of each point on a grid of 2^bits cells per axis over bbox
 * {xmin,ymin,zmin,xmax,ymax,zmax} (3*bits <= 63).  Point i is at xyz + i*stride (doubles).
 * Points outside the box are clamped.  threads <= 1: serial. */
void sort_moore_keys(const double *xyz, size_t stride, size_t n, const double bbox[6], int bits,
                     uint64_t *keys, int threads);

/* Stable sort of idx[0..n) by keys (keys permuted alongside), looking only at the low
 * key_bits bits.  tmp_keys / tmp_idx are caller-provided scratch of n entries each.
 * threads <= 1: serial. */
void sort_radix_pairs(uint64_t *keys, uint32_t *idx, size_t n, int key_bits,
                      uint64_t *tmp_keys, uint32_t *tmp_idx, int threads);

/* The BRIO order of points xyz[i*stride] for the listed point ids ids[0..n):
 * shuffle by a hash of (id, seed), cut into rounds (the first of at most `first` points, each
 * next about `ratio` times larger), and sort each round on the Moore curve of the points'
 * bounding box.  On return ids[] holds the insertion order and round_end[r] (r <
 * *num_rounds <= 64) the exclusive end of round r.  Returns GTET_OK or
 * GTET_ERR_OUT_OF_MEMORY. */
gtet_status sort_brio(const double *xyz, size_t stride, uint32_t *ids, size_t n, uint64_t seed,
                      size_t first, double ratio, size_t round_end[64], int *num_rounds,
                      int threads);

#endif
