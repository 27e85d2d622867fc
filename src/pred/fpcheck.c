/* fpcheck.c -- run-time check of the floating-point model the filters and expansions assume
 * (fpenv.h).  Inputs come from volatile objects so that the compiler cannot fold the
 * expressions at compile time: what is tested is the arithmetic of the code as compiled with
 * this translation unit's flags (the same flags as the predicates).
 *   rounding:    1 + 0.75*2^-52 must round up to 1 + 2^-52 (not toward 0 / -inf) and
 *                -1 - 0.75*2^-52 to -(1 + 2^-52) (not toward +inf); 1 + 2^-53 is a tie and must
 *                go to the even neighbour 1 (and 1 + 3*2^-53 to 1 + 2^-51).
 *   contraction: a = 1 + 2^-30, b = 1 - 2^-30: a*b = 1 - 2^-60 rounds to 1, so a*b - 1 == 0;
 *                a fused multiply-add gives -2^-60.
 *   extended:    (1 + 2^-53) - 1 == 0 in binary64; 2^-53 with a wider intermediate format.
 *   denormals:   2^-1022 / 2 == 2^-1023 != 0 (no flush to zero) and 2^-1074 + 2^-1074 ==
 *                2^-1073 (denormal inputs not treated as zero).
 */
#include "pred.h"

int pred_fp_selftest(void)
{
    volatile double one = 1.0, q = 0x1.8p-53, tie = 0x1p-53, tie3 = 0x1.8p-52;
    volatile double fa = 1.0 + 0x1p-30, fb = 1.0 - 0x1p-30;
    volatile double dmin = 0x1p-1022, two = 2.0, dtiny = 0x1p-1074;
    int bad = 0;

    double o = one, x = q;
    volatile double up = o + x, down = -o - x;
    if (up != 1.0 + 0x1p-52 || down != -(1.0 + 0x1p-52)) bad |= PRED_FP_BAD_ROUNDING;
    volatile double t1 = o + (double)tie, t3 = o + (double)tie3;
    if (t1 != 1.0 || t3 != 1.0 + 0x1p-51) bad |= PRED_FP_BAD_ROUNDING;

    double a = fa, b = fb;
    volatile double r = a * b - o;
    if (r != 0.0) bad |= PRED_FP_CONTRACTION;

    volatile double ext = (o + (double)tie) - o;
    if (ext != 0.0) bad |= PRED_FP_EXTENDED;

    volatile double half = dmin / two, sum = dtiny + dtiny;
    if (half == 0.0 || half != 0x1p-1023 || sum != 0x1p-1073) bad |= PRED_FP_DENORMALS;
    return bad;
}
