/* exact_gmp.c -- the last exact stage: GMP mpz on the exact integer form of the doubles.
 *
 * Every finite double is m * 2^k with an integer m (|m| < 2^53) and k >= -1074.  With K the
 * smallest k over the nonzero coordinates of the tuple, every coordinate is the integer
 * m * 2^(k-K) times the common factor 2^K; the determinants are homogeneous, so their sign is the
 * sign of the same determinant on these integers, computed exactly in mpz (no size limit).
 * Correct for every finite input: denormals, 2^1000, mixtures.  Slow (allocations), so it runs
 * only when the integer and expansion stages do not apply.  This is not the oracle: tests
 * compare all stages against src/oracle (mpq, written separately).
 */
#include "pred_internal.h"

#include <gmp.h>
#include <math.h>

#define NMAX 15

/* z[i] = x[i] / 2^K as integers, for n coordinates */
static void to_integers(const double *x, int n, mpz_t *z)
{
    int K = 1 << 20;
    int kk[NMAX];
    double mant[NMAX];
    for (int i = 0; i < n; i++) {
        int e = 0;
        mant[i] = 0;
        kk[i] = 0;
        if (x[i] == 0) continue;
        double f = frexp(x[i], &e);    /* x = f * 2^e, 0.5 <= |f| < 1, exact */
        mant[i] = ldexp(f, 53);        /* integer, |.| < 2^53, exact */
        kk[i] = e - 53;
        if (kk[i] < K) K = kk[i];
    }
    for (int i = 0; i < n; i++) {
        mpz_set_d(z[i], mant[i]);
        if (x[i] != 0) mpz_mul_2exp(z[i], z[i], (mp_bitcnt_t)(kk[i] - K));
    }
}

static void load(const double *const *pts, int n, mpz_t *z)
{
    double x[NMAX];
    for (int k = 0; k < n; k++)
        for (int j = 0; j < 3; j++) x[3 * k + j] = pts[k][j];
    to_integers(x, 3 * n, z);
}

/* r = det of the 3x3 matrix rows p, q, r (coordinates c0, c1, c2) */
static void det3(mpz_t r, mpz_t *p, mpz_t *q, mpz_t *s, mpz_t t1, mpz_t t2)
{
    /* p0*(q1 s2 - q2 s1) + p1*(q2 s0 - q0 s2) + p2*(q0 s1 - q1 s0) */
    mpz_set_ui(r, 0);
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        mpz_mul(t1, q[i], s[j]);
        mpz_submul(t1, q[j], s[i]);
        mpz_mul(t2, p[k], t1);
        mpz_add(r, r, t2);
    }
}

int pred_orient3d_gmp(const double *a, const double *b, const double *c, const double *d)
{
    const double *pts[4] = {a, b, c, d};
    mpz_t z[12], r, t1, t2;
    for (int i = 0; i < 12; i++) mpz_init(z[i]);
    mpz_inits(r, t1, t2, NULL);
    load(pts, 4, z);
    for (int k = 1; k < 4; k++)
        for (int j = 0; j < 3; j++) mpz_sub(z[3 * k + j], z[3 * k + j], z[j]);
    det3(r, z + 3, z + 6, z + 9, t1, t2);
    int s = mpz_sgn(r);
    for (int i = 0; i < 12; i++) mpz_clear(z[i]);
    mpz_clears(r, t1, t2, NULL);
    return s;
}

int pred_insphere_gmp(const double *a, const double *b, const double *c, const double *d,
                      const double *e)
{
    /* insphere = -det4[(p-e, |p-e|^2)] = sum_k (-1)^k w_k det3(other rows, in order)
     * (expansion of det4 along the w column: det4 = sum_k (-1)^(k+3) w_k M_k, 0-based k) */
    const double *pts[5] = {a, b, c, d, e};
    mpz_t z[15], w[4], r, m, t1, t2;
    for (int i = 0; i < 15; i++) mpz_init(z[i]);
    for (int i = 0; i < 4; i++) mpz_init(w[i]);
    mpz_inits(r, m, t1, t2, NULL);
    load(pts, 5, z);
    for (int k = 0; k < 4; k++) {
        for (int j = 0; j < 3; j++) mpz_sub(z[3 * k + j], z[3 * k + j], z[12 + j]);
        mpz_mul(w[k], z[3 * k], z[3 * k]);
        mpz_addmul(w[k], z[3 * k + 1], z[3 * k + 1]);
        mpz_addmul(w[k], z[3 * k + 2], z[3 * k + 2]);
    }
    mpz_set_ui(r, 0);
    for (int k = 0; k < 4; k++) {
        int o[3], n = 0;
        for (int i = 0; i < 4; i++)
            if (i != k) o[n++] = i;
        det3(m, z + 3 * o[0], z + 3 * o[1], z + 3 * o[2], t1, t2);
        if (k & 1)
            mpz_submul(r, w[k], m);
        else
            mpz_addmul(r, w[k], m);
    }
    int s = mpz_sgn(r);
    for (int i = 0; i < 15; i++) mpz_clear(z[i]);
    for (int i = 0; i < 4; i++) mpz_clear(w[i]);
    mpz_clears(r, m, t1, t2, NULL);
    return s;
}

int pred_orient2d_gmp(const double *a, const double *b, const double *c, int u, int w)
{
    const double *pts[3] = {a, b, c};
    mpz_t z[9], t;
    for (int i = 0; i < 9; i++) mpz_init(z[i]);
    mpz_init(t);
    load(pts, 3, z);
    for (int k = 1; k < 3; k++)
        for (int j = 0; j < 3; j++) mpz_sub(z[3 * k + j], z[3 * k + j], z[j]);
    /* (b-a)_u (c-a)_w - (b-a)_w (c-a)_u */
    mpz_mul(t, z[3 + u], z[6 + w]);
    mpz_submul(t, z[3 + w], z[6 + u]);
    int s = mpz_sgn(t);
    for (int i = 0; i < 9; i++) mpz_clear(z[i]);
    mpz_clear(t);
    return s;
}

int pred_lifted2d_gmp(const double *a, const double *b, const double *c, const double *e,
                      int u, int w)
{
    const double *pts[4] = {a, b, c, e};
    mpz_t z[12], r, l, m;
    for (int i = 0; i < 12; i++) mpz_init(z[i]);
    mpz_inits(r, l, m, NULL);
    load(pts, 4, z);
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) mpz_sub(z[3 * k + j], z[3 * k + j], z[9 + j]);
    mpz_set_ui(r, 0);
    for (int k = 0; k < 3; k++) {
        mpz_t *q = z + 3 * ((k + 1) % 3), *s = z + 3 * ((k + 2) % 3), *p = z + 3 * k;
        mpz_mul(m, q[u], s[w]);
        mpz_submul(m, s[u], q[w]);
        mpz_mul(l, p[0], p[0]);
        mpz_addmul(l, p[1], p[1]);
        mpz_addmul(l, p[2], p[2]);
        mpz_addmul(r, l, m);
    }
    int s = mpz_sgn(r);
    for (int i = 0; i < 12; i++) mpz_clear(z[i]);
    mpz_clears(r, l, m, NULL);
    return s;
}
