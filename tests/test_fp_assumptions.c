/* test_fp_assumptions.c -- the floating-point model of the predicates holds in this build.
 *
 * pred_fp_selftest() checks round-to-nearest-even, no contraction of a*b+c, no extended
 * precision and no flush-to-zero at run time (fpcheck.c).  This test passes in the normal
 * build.  tests/pred.cmake builds the same program a second time from the predicate sources
 * compiled with -ffp-contract=fast -mfma and registers it with WILL_FAIL: the suite thereby
 * proves that the check fails when its assumption is broken.  (A -ffast-math build does not
 * even compile: fpenv.h stops it; also a WILL_FAIL test in tests/pred.cmake.)
 */
#include "pred/pred.h"
#include "testutil.h"

/* Exercises proofs/filters.md §5 (the IEEE assumptions the certified constants rely on). */
static void test_fp_model_round_to_nearest_no_fma_no_extended_no_ftz(void)
{
    int bad = pred_fp_selftest();
    TEST_CHECK(!(bad & PRED_FP_BAD_ROUNDING), "rounding is not to nearest even");
    TEST_CHECK(!(bad & PRED_FP_CONTRACTION), "a*b-c was contracted into an FMA");
    TEST_CHECK(!(bad & PRED_FP_EXTENDED), "intermediates carry extended precision");
    TEST_CHECK(!(bad & PRED_FP_DENORMALS), "denormals are flushed to zero");
    TEST_CHECK(bad == 0, "pred_fp_selftest() = %d", bad);
}

int main(void)
{
    TU_RUN(test_fp_model_round_to_nearest_no_fma_no_extended_no_ftz);
    return tu_finish();
}
