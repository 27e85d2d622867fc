/* pred_internal.h -- the stages of the predicates, exposed for the predicate files, the tests
 * and the stage benchmark (not for the kernel, which uses pred.h).
 *
 * Every exact stage returns 1 and stores the exact sign in *sign when it applies to its input,
 * 0 when the input is outside its domain (the caller then tries the next stage):
 *   _int : all coordinates are integers below a bound (derived in exact_int.c)
 *   _wide: the exact integer form of the tuple (one common power of two removed) fits 60 bits
 *   _exp : expansions; all nonzero coordinates fit the band after a power-of-two scaling
 *          (pred_band_scale); insphere also needs exactly representable translations p - e
 *   _gmp : always applies (returns the sign directly).
 * Axis pairs (u, w) select a coordinate plane: (0,1) xy, (1,2) yz, (0,2) xz.
 */
#ifndef GTET_PRED_INTERNAL_H
#define GTET_PRED_INTERNAL_H

#include "pred.h"

/* Band of the expansion stage: every nonzero |coordinate| in [2^-150, 2^150).  Then every
 * coordinate (and every difference of two) is a multiple of 2^-202, a degree-k product term is
 * a multiple of 2^(-202k) >= 2^-1010 (k <= 5) and below 2^770, so no Two-Product tail
 * underflows and no Dekker split (x * (2^27+1)) overflows: the expansions are exact. */
#define PRED_BAND_LO_EXP (-150)
#define PRED_BAND_HI_EXP 150

/* Copy the 3*n coordinates of pts[0..n-1] into out[3*n], multiplied by one power of two
 * chosen so that every nonzero coordinate lies in the band (signs of homogeneous predicates
 * are unchanged by a positive scaling; a power-of-two scaling into the normal range is exact).
 * Returns 0 when no such scaling exists (the exponents span more than 299 binades). */
int pred_band_scale(const double *const *pts, int n, double *out);

int pred_orient3d_int(const double *a, const double *b, const double *c, const double *d,
                      int *sign);
int pred_insphere_int(const double *a, const double *b, const double *c, const double *d,
                      const double *e, int *sign);
/* pred_insphere_int (with known = 1: the caller knows that every coordinate is an integer of
 * magnitude < 2^23, pred_static.int23, and the checks are skipped) that, when the sign is 0
 * and mn is not NULL, also stores the exact 3x3
 * minors abc, bcd, cda, dab of the translated points a - e, ... in mn[0..3] (the order and
 * signs of pred_insphere_filter's minors): the perturbation reads its orient3d signs off them
 * (sos.c).  |minor| < 2^75. */
__extension__ typedef __int128 pred_i128;
int pred_insphere_int_m(const double *a, const double *b, const double *c, const double *d,
                        const double *e, int known, int *sign, pred_i128 *mn);
/* orient3d / insphere on the exact integer form of the tuple (common power of two removed)
 * when every integer is below 2^60: 64/128/192(/320)-bit fixed-width evaluation
 * (exact_int.c). */
int pred_orient3d_wide(const double *a, const double *b, const double *c, const double *d,
                       int *sign);
int pred_insphere_wide(const double *a, const double *b, const double *c, const double *d,
                       const double *e, int *sign);
/* insphere on the same integer form when every integer is below 2^122 (a tuple spanning up
 * to 122 binades), in digit vectors of radix 2^60 on the stack (exact_int.c) */
int pred_insphere_wide122(const double *a, const double *b, const double *c, const double *d,
                          const double *e, int *sign);
int pred_orient2d_int(const double *a, const double *b, const double *c, int u, int w,
                      int *sign);
/* sign of det[(u,w,|.|^2) of a-e; b-e; c-e] (see sos.c) */
int pred_lifted2d_int(const double *a, const double *b, const double *c, const double *e,
                      int u, int w, int *sign);
/* the same two on the wide integer form (any tuple whose bits span <= 60 binades) */
int pred_orient2d_wide(const double *a, const double *b, const double *c, int u, int w,
                       int *sign);
int pred_lifted2d_wide(const double *a, const double *b, const double *c, const double *e,
                       int u, int w, int *sign);
/* (b-a)_u (c-a)_w - (b-a)_w (c-a)_u exactly, on any finite doubles */
int pred_orient2d_exact(const double *a, const double *b, const double *c, int u, int w);
/* its exact sign on any finite doubles: small integers, wide form, then GMP */
int pred_lifted2d_exact(const double *a, const double *b, const double *c, const double *e,
                        int u, int w);

int pred_orient3d_exp(const double *a, const double *b, const double *c, const double *d,
                      int *sign);
int pred_insphere_exp(const double *a, const double *b, const double *c, const double *d,
                      const double *e, int *sign);

int pred_orient3d_gmp(const double *a, const double *b, const double *c, const double *d);
int pred_insphere_gmp(const double *a, const double *b, const double *c, const double *d,
                      const double *e);
int pred_orient2d_gmp(const double *a, const double *b, const double *c, int u, int w);
int pred_lifted2d_gmp(const double *a, const double *b, const double *c, const double *e,
                      int u, int w);

#endif
