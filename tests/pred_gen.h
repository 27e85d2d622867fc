/* pred_gen.h -- point-tuple generators shared by the predicate tests and the stage-count
 * program: random doubles, ulp neighbours of exactly degenerate configurations, integer grids,
 * lattice points of integer spheres, points rounded onto a sphere, extreme magnitudes. */
#ifndef GTET_PRED_GEN_H
#define GTET_PRED_GEN_H

#include "testutil.h"

#include <float.h>
#include <math.h>
#include <stdint.h>

/* uniform integer in [-m, m] */
static inline int64_t pg_int(tu_rng *r, int64_t m) { return (int64_t)tu_below(r, 2 * (uint64_t)m + 1) - m; }

/* a random finite double: random sign, exponent in [elo, ehi], random 52-bit mantissa;
 * elo == -1074 allows subnormals */
static inline double pg_double_exp(tu_rng *r, int elo, int ehi)
{
    int e = elo + (int)tu_below(r, (uint64_t)(ehi - elo + 1));
    double m = 1.0 + (double)(tu_next(r) >> 12) * 0x1p-52;
    double x = ldexp(m, e);
    if (x > DBL_MAX) x = DBL_MAX;
    return (tu_next(r) & 1) ? -x : x;
}

/* move x by k ulps (k in [-2, 2]), staying finite */
static inline double pg_ulps(double x, int k)
{
    for (; k > 0; k--) x = nextafter(x, DBL_MAX);
    for (; k < 0; k++) x = nextafter(x, -DBL_MAX);
    return x;
}

/* perturb one random coordinate of one of n points by -2..2 ulps (0 keeps it exact) */
static inline void pg_perturb(tu_rng *r, double (*p)[3], int n)
{
    int k = (int)tu_below(r, 5) - 2;
    int i = (int)tu_below(r, (uint64_t)n), j = (int)tu_below(r, 3);
    p[i][j] = pg_ulps(p[i][j], k);
}

/* Lattice points on the sphere x^2+y^2+z^2 = R2: fills pts (up to cap), returns the count. */
static inline int pg_sphere_lattice(int64_t R2, int64_t (*pts)[3], int cap)
{
    int n = 0;
    int64_t R = (int64_t)sqrt((double)R2) + 1;
    for (int64_t x = -R; x <= R; x++)
        for (int64_t y = -R; y <= R; y++) {
            int64_t z2 = R2 - x * x - y * y;
            if (z2 < 0) continue;
            int64_t z = (int64_t)sqrt((double)z2);
            while (z * z > z2) z--;
            while ((z + 1) * (z + 1) <= z2) z++;
            if (z * z != z2) continue;
            for (int s = 0; s < (z ? 2 : 1) && n < cap; s++) {
                pts[n][0] = x;
                pts[n][1] = y;
                pts[n][2] = s ? -z : z;
                n++;
            }
        }
    return n;
}

#endif
