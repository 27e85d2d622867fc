/* oracle_small.c -- the oracle's exact path for points whose coordinates, at the common
 * power-of-two scale of oracle.c, are integers below 2^22 in magnitude (integer grids, small
 * dyadic coordinates): the same polynomials as the GMP path, in 128-bit integers.
 *
 * Why nothing overflows (B = ORC_SMALL_BITS = 22, |coordinate| < 2^B):
 *   differences       |d| < 2^(B+1)
 *   lifted entries    |x-e|^2 summed over 3 axes < 3 * 2^(2B+2) < 2^(2B+4)
 *   2x2 minors        < 2 * 2^(2B+2) = 2^(2B+3)
 *   3x3 determinants  < 3 * 2^(B+1) * 2^(2B+3) < 2^(3B+6)   (= 2^72)
 *   insphere 4x4      < 4 * 2^(2B+4) * 2^(3B+6) = 2^(5B+12) (= 2^122 < 2^127)
 * so every intermediate fits a signed __int128 and the signs are exact.  GCC and Clang provide
 * __int128 on 64-bit targets (__extension__ keeps -Wpedantic quiet).  The results are compared
 * with an mpq reference and with CGAL in tests/test_oracle_predicates.c, test_oracle_cgal.cpp.
 */
#include "oracle_small.h"

#include <limits.h>

__extension__ typedef __int128 i128;

int orc_small_load(orc_small *s, const double *const *p, int k)
{
    double m[5][3];
    int e[5][3], emin = INT_MAX;
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++) {
            orc_split_double(p[i][j], &m[i][j], &e[i][j]);
            if (m[i][j] != 0.0 && e[i][j] < emin) emin = e[i][j];
        }
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++) {
            if (m[i][j] == 0.0) {
                s->c[i][j] = 0;
                continue;
            }
            /* |m| * 2^shift < 2^B  <=>  shift < B and |m| < 2^(B - shift) */
            int shift = e[i][j] - emin;
            double am = m[i][j] < 0 ? -m[i][j] : m[i][j];
            if (shift >= ORC_SMALL_BITS || am >= (double)((int64_t)1 << (ORC_SMALL_BITS - shift)))
                return 0;
            s->c[i][j] = (int64_t)m[i][j] * ((int64_t)1 << shift);  /* exact: < 2^B */
        }
    return 1;
}

static i128 det3(const i128 u[3], const i128 v[3], const i128 w[3])
{
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static int sign128(i128 x) { return (x > 0) - (x < 0); }

int orc_small_orient3d(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d)
{
    i128 u[3], v[3], w[3];
    for (int j = 0; j < 3; j++) {
        u[j] = (i128)b[j] - a[j];
        v[j] = (i128)c[j] - a[j];
        w[j] = (i128)d[j] - a[j];
    }
    return sign128(det3(u, v, w));
}

/* -sign det[x-e, |x-e|^2] (rows x = a,b,c,d), expanded along the lifted column as in oracle.c */
int orc_small_insphere(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d,
                       const int64_t *e)
{
    const int64_t *p[4] = {a, b, c, d};
    i128 r[4][3], lift[4];
    for (int i = 0; i < 4; i++) {
        lift[i] = 0;
        for (int j = 0; j < 3; j++) {
            r[i][j] = (i128)p[i][j] - e[j];
            lift[i] += r[i][j] * r[i][j];
        }
    }
    i128 det = 0;
    for (int i = 0; i < 4; i++) {
        const i128 *rows[3];
        int k = 0;
        for (int row = 0; row < 4; row++)
            if (row != i) rows[k++] = r[row];
        i128 t = lift[i] * det3(rows[0], rows[1], rows[2]);
        det = (i + 3) % 2 == 0 ? det + t : det - t;
    }
    return -sign128(det);
}
