/* validate.h -- input validation (prefix kval_): finite coordinates, exact duplicates and the
 * affine dimension of the input, all in linear time. */
#ifndef GTET_VALIDATE_H
#define GTET_VALIDATE_H

#include <stddef.h>
#include <stdint.h>

#include "../base/base.h"
#include "../pred/pred.h"

/* Reject NaN and infinite coordinates (GTET_ERR_NONFINITE naming the first bad index). */
gtet_status kval_finite(const double *xyz, size_t n, int threads, gtet_error *err);

/* Exact duplicate detection (-0.0 == +0.0) in expected linear time, on up to `threads`
 * threads (the same result for any count).  On success *verts holds the 3*(*nv) coordinates
 * of the distinct points in order of first occurrence (signed zeros as given by the first
 * occurrence), *map the vertex id of every input point.  n < 2^31. */
gtet_status kval_dedup(const double *xyz, size_t n, int threads, double **verts, uint32_t **map,
                       size_t *nv, gtet_error *err);

/* kval_dedup's method from 65536 points on (validate.c: buckets by hash, one small table per
 * bucket), on T >= 1 threads; exposed for the tests, which compare it with the single table
 * kval_dedup uses below that size. */
gtet_status kval_dedup_partitioned(const double *xyz, size_t n, int T, double **verts,
                                   uint32_t **map, size_t *nv, gtet_error *err);

/* Find four affinely independent vertices, scanning ids in the given order: the first vertex,
 * the first one different from it, the first not collinear with those, the first not coplanar
 * with those three.  Returns their positions in order[] (pos[0] == 0) and GTET_OK, or
 * GTET_ERR_DEGENERATE_INPUT with the affine dimension (0, 1 or 2) in err.  Linear time. */
gtet_status kval_first_simplex(const double *verts, const uint32_t *order, size_t nv,
                               size_t pos[4], pred_counters *cnt, gtet_error *err);

#endif
