/* testutil.h -- the small test harness every tests/test_*.c uses.
 *
 * TEST_CHECK(cond, fmt, ...) records a failure with file/line and a message and goes on;
 * TEST_REQUIRE returns from the current test function on failure.  tu_run() runs a named test
 * function and main() ends with `return tu_finish();`, which prints the plain closing line
 * "N passed, N failed" and returns non-zero on any failure.  tu_rng is a reproducible
 * 64-bit generator (splitmix64), never rand().
 */
#ifndef GTET_TESTUTIL_H
#define GTET_TESTUTIL_H

#include <stdint.h>
#include <stdio.h>

extern int tu_current_failed;

void tu_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void tu_run(const char *name, void (*fn)(void));
int tu_finish(void);

#define TEST_CHECK(cond, ...) \
    do { if (!(cond)) tu_fail(__FILE__, __LINE__, __VA_ARGS__); } while (0)
#define TEST_REQUIRE(cond, ...) \
    do { if (!(cond)) { tu_fail(__FILE__, __LINE__, __VA_ARGS__); return; } } while (0)
#define TU_RUN(fn) tu_run(#fn, fn)

/* GTET_TEST_SANITIZED: built with ASan or TSan (gcc's macros, clang's __has_feature), where a
 * test runs a smaller problem so that the sanitized CI job stays within its time. */
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define GTET_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define GTET_TEST_SANITIZED 1
#endif
#endif

typedef struct tu_rng { uint64_t s; } tu_rng;
static inline uint64_t tu_next(tu_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
/* uniform in [0,1) with 53 random bits */
static inline double tu_uniform(tu_rng *r) { return (double)(tu_next(r) >> 11) * 0x1p-53; }
/* uniform integer in [0, m) */
static inline uint64_t tu_below(tu_rng *r, uint64_t m) { return tu_next(r) % m; }

#endif
