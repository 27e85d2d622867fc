/* oracle_small.h -- internal to src/oracle/: the oracle's exact small-integer path. */
#ifndef GTET_ORACLE_SMALL_H
#define GTET_ORACLE_SMALL_H

#include <stdint.h>

/* Coordinates as integers at one common power-of-two scale, when every one of them is below
 * 2^ORC_SMALL_BITS in magnitude (then orient3d and insphere are exact in __int128). */
#define ORC_SMALL_BITS 22

typedef struct orc_small {
    int64_t c[5][3];
} orc_small;

/* x = m * 2^e with m odd (|m| < 2^53); x == 0 gives m = 0.  Defined in oracle.c. */
void orc_split_double(double x, double *m, int *e);

/* Fill s with the k <= 5 points scaled by the common power of two of oracle.c; 1 when every
 * scaled coordinate is below 2^ORC_SMALL_BITS, else 0 (s unusable). */
int orc_small_load(orc_small *s, const double *const *p, int k);
int orc_small_orient3d(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d);
int orc_small_insphere(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d,
                       const int64_t *e);

#endif
