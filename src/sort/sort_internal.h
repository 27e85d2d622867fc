/* sort_internal.h -- functions shared by the files of src/sort only (not part of sort.h). */
#ifndef GTET_SORT_INTERNAL_H
#define GTET_SORT_INTERNAL_H

#include "sort.h"

/* keys[i] = round[i] << round_shift | (Moore key of the point xyz + ids[i]*stride on bbox with
 * `bits` bits per axis), as sort_moore_keys_ids computes it: the BRIO's keys, one stable sort
 * away from its order.  round[i] < num_rounds <= 64, 3 * bits <= round_shift,
 * round_shift + 6 <= 64. */
void sort_moore_keys_rounds(const double *xyz, size_t stride, const uint32_t *ids, size_t n,
                            const uint8_t *round, int num_rounds, const double bbox[6], int bits,
                            int round_shift, uint64_t *keys, int threads);

#endif
