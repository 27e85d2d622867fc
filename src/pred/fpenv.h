/* fpenv.h -- the floating-point assumptions of the predicates, enforced at compile time.
 *
 * The filter constants (proofs/) and the expansion arithmetic assume IEEE 754 binary64,
 * round-to-nearest-even, every operation rounded once to double (no x87 extended precision:
 * FLT_EVAL_METHOD == 0) and no contraction of a*b+c into an FMA (built with
 * -ffp-contract=off), no -ffast-math.  What can be checked by the preprocessor is checked here;
 * the rest at run time by pred_fp_selftest() (tests/test_fp_assumptions.c).
 */
#ifndef GTET_FPENV_H
#define GTET_FPENV_H

#include <float.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "gigatet predicates need FLT_EVAL_METHOD == 0 (SSE2 double arithmetic, no x87)"
#endif
#if defined(__FAST_MATH__)
#error "gigatet predicates must not be compiled with -ffast-math"
#endif
#if DBL_MANT_DIG != 53 || DBL_MAX_EXP != 1024 || DBL_MIN_EXP != -1021 || FLT_RADIX != 2
#error "gigatet predicates need IEEE 754 binary64 doubles"
#endif

enum {
    PRED_FP_BAD_ROUNDING = 1,    /* not round-to-nearest */
    PRED_FP_CONTRACTION = 2,     /* a*b+c was fused */
    PRED_FP_EXTENDED = 4,        /* intermediate results carried extra precision */
    PRED_FP_DENORMALS = 8        /* denormals flushed to zero (FTZ/DAZ) */
};

#endif
