/* fuzz_common.h -- shared helpers of the fuzz targets (fuzz/fuzz_*.c).
 *
 * fz_bytes turns the fuzzer's bytes into numbers: every read past the end returns zeros, so
 * every byte string is a valid input and short inputs are still meaningful.  fz_coord draws
 * one coordinate from the adversarial families the predicates must get right: raw doubles
 * (any finite bit pattern), small integers, 1-ulp neighbours of an earlier value, small
 * integers scaled by 2^+-1000, and denormals.  FZ_ASSERT prints what failed and aborts: that
 * is what libFuzzer and the corpus replay (fuzz/replay_main.c) detect as a finding.
 * Header-only (static functions) so every target stays one translation unit.
 */
#ifndef GTET_FUZZ_COMMON_H
#define GTET_FUZZ_COMMON_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* libFuzzer's entry point; fuzz/replay_main.c calls it in the ordinary test build. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FZ_ASSERT(cond, ...)                                                         \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: fuzz assertion failed: %s: ", __FILE__, __LINE__, \
                    #cond);                                                          \
            fprintf(stderr, __VA_ARGS__);                                            \
            fputc('\n', stderr);                                                     \
            abort();                                                                 \
        }                                                                            \
    } while (0)

typedef struct fz_bytes {
    const uint8_t *p;
    size_t n, at;
} fz_bytes;

static inline uint8_t fz_u8(fz_bytes *b) { return b->at < b->n ? b->p[b->at++] : 0; }

static inline uint64_t fz_u64(fz_bytes *b)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)fz_u8(b) << (8 * i);
    return v;
}

static inline int fz_small_int(fz_bytes *b) { return (int)(fz_u8(b) % 17) - 8; } /* -8..8 */

static inline size_t fz_left(const fz_bytes *b) { return b->at < b->n ? b->n - b->at : 0; }

/* A finite double from 8 raw bytes (NaN / Inf bit patterns become their mantissa, finite). */
static inline double fz_raw_double(fz_bytes *b)
{
    uint64_t u = fz_u64(b);
    double d;
    memcpy(&d, &u, sizeof d);
    if (!isfinite(d)) {
        u &= ~(0x7ffULL << 52);  /* clear the exponent: a denormal or zero, still finite */
        memcpy(&d, &u, sizeof d);
    }
    return d;
}

/* n ulp steps from x (towards +inf for k > 0); stays finite. */
static inline double fz_ulps(double x, int k)
{
    for (; k > 0; k--) x = nextafter(x, INFINITY);
    for (; k < 0; k++) x = nextafter(x, -INFINITY);
    return isfinite(x) ? x : 0.0;
}

/* One coordinate of an adversarial family; prev[0..nprev) are earlier values (any axis) that
 * the 1-ulp family perturbs. */
static inline double fz_coord(fz_bytes *b, const double *prev, size_t nprev)
{
    uint8_t fam = fz_u8(b) % 8;
    switch (fam) {
    case 0:
        return fz_raw_double(b);
    case 1:
    case 2:
        return (double)fz_small_int(b);
    case 3: {                               /* 1..3 ulps away from an earlier value */
        double base = nprev ? prev[fz_u8(b) % nprev] : (double)fz_small_int(b);
        int k = (int)(fz_u8(b) % 7) - 3;
        return fz_ulps(base, k);
    }
    case 4:
        return ldexp((double)fz_small_int(b), 1000);
    case 5:
        return ldexp((double)fz_small_int(b), -1000);
    case 6:                                 /* denormal: k * 2^-1074 */
        return ldexp((double)fz_small_int(b), -1074);
    default: {                              /* a small dyadic: k / 2^j */
        int k = fz_small_int(b);
        return ldexp((double)k, -(int)(fz_u8(b) % 60));
    }
    }
}

#endif
