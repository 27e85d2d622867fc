/* parallel_race_canary.c -- a deliberately racy OpenMP program: the TSan job's proof that it
 * can fail (issue 4, "Race freedom").
 *
 * Every thread increments one shared counter with a plain, unsynchronised read-modify-write.
 * That is a data race by the C memory model, so a working ThreadSanitizer + Archer set-up
 * must report "WARNING: ThreadSanitizer: data race" here; tests/verify.cmake registers this
 * program (only in the GTET_TSAN build) as the ctest tsan_flags_a_deliberate_data_race, which
 * passes only when that report appears.  Were TSan or Archer missing or misconfigured (e.g.
 * libgomp instead of LLVM's libomp, whose barriers TSan cannot see without Archer), the
 * report of a real race in the kernel could be silent too: this canary makes that visible.
 * The counter goes through a volatile pointer so the compiler cannot hoist or merge the
 * increments out of the loop.
 */
#include <omp.h>
#include <stdio.h>

static long counter;

int main(void)
{
    volatile long *c = &counter;
    int threads = 0;
#pragma omp parallel num_threads(4)
    {
#pragma omp single
        threads = omp_get_num_threads();
#pragma omp for schedule(static)
        for (int i = 0; i < 400000; i++) *c = *c + 1;  /* the race */
    }
    printf("threads %d, counter %ld (400000 without the race)\n", threads, counter);
    return threads >= 2 ? 0 : 1;
}
