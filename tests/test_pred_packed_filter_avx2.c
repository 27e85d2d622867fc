/* test_pred_packed_filter_avx2.c -- test_pred_packed_filter.c compiled with AVX2 (tests/pred.cmake),
 * where filter_packed.h's filters evaluate det~ four lanes at a time (pred_insphere_lanes4_,
 * what kernel/insert_avx2.c runs): the same specification, the same tuples, the answers and
 * records compared byte for byte with the scalar filter's.  On a CPU without AVX2 the library
 * never runs that code and this test cannot: it says so and passes; a build without the AVX2
 * translation unit has nothing to compare. */
#if defined(__AVX2__)
#include <stdio.h>
int packed_main(void);
#define main packed_main
#include "test_pred_packed_filter.c"
#undef main

int main(void)
{
#ifndef PRED_INSPHERE_PACKED4
#error "filter.h has no four-lane filter under AVX2"
#endif
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2")) {
        printf("this CPU has no AVX2: the library runs the two-lane filter here\n");
        return 0;
    }
    return packed_main();
}
#else
#include <stdio.h>

int main(void)
{
    printf("built without AVX2 (no kernel/insert_avx2.c in this build): nothing to compare\n");
    return 0;
}
#endif
