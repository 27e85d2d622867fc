/* exact_exp.c -- expansion stage of orient3d and insphere (expansion.h arithmetic).
 *
 * Both predicates first bring the tuple into the band of pred_internal.h by one power-of-two
 * scaling (exact; signs of homogeneous polynomials of odd/any degree are unchanged by a
 * positive factor).  Then:
 *   - translated form, when every translated coordinate (b-a for orient3d, p-e for insphere)
 *     is exact as a double (checked with Two-Diff tails == 0; true on most near-degenerate
 *     inputs of moderate spread): the filter's formula evaluated with expansions.  Lengths:
 *     2x2 minor <= 4, 3x3 <= 24, lift <= 6, lift*3x3 <= 288, insphere <= 1152, orient3d <= 24.
 *   - otherwise, orient3d only: raw form, on the untranslated coordinates,
 *       orient3d(p,q,r,s) = T(q,r,s) - T(p,r,s) + T(p,q,s) - T(p,q,r), T = det3 of raw rows
 *         (cofactor expansion of det[[p,1],[q,1],[r,1],[s,1]] = -orient3d along the 1-column);
 *     lengths: T <= 24, orient3d <= 96.  For insphere with an inexact translation we return
 *     "not applicable" and the caller uses GMP: the filter's formula on two-component
 *     translated coordinates (with the raw 5x5 form, lifts times orientations, as fallback)
 *     is slower than the GMP stage on points rounded onto the unit sphere, so it is not kept
 *     (NOTES.md D7).  The orient3d raw form is faster than GMP on the same tuples (D7).
 * Each 3x3 minor, lift and orientation is compressed (exp_compress) before it is multiplied:
 * the value is unchanged and the products stay short (the bounds above are worst cases).
 * The band guarantees that every Two-Product is exact (expansion.h), so the result is exact.
 */
#include "expansion.h"
#include "pred_internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

static int biased_exp(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return (int)((u >> 52) & 0x7ff);
}

int pred_band_scale(const double *const *pts, int n, double *out)
{
    int lo = 1 << 20, hi = -(1 << 20), inband = 1;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < 3; j++) {
            double x = pts[k][j];
            out[3 * k + j] = x;
            if (x == 0) continue;
            int be = biased_exp(x);
            /* normal x in [2^-150, 2^150): biased exponent in [1023-150, 1023+149] */
            if (be < 1023 + PRED_BAND_LO_EXP || be > 1023 + PRED_BAND_HI_EXP - 1) inband = 0;
            int e = be == 0 ? ilogb(x) : be - 1023; /* ilogb is exact for subnormals */
            if (e < lo) lo = e;
            if (e > hi) hi = e;
        }
    if (inband) return 1;
    if (hi - lo > PRED_BAND_HI_EXP - 1 - PRED_BAND_LO_EXP) return 0;
    int s = PRED_BAND_LO_EXP - lo; /* lo + s = -150 and hi + s <= 149 */
    for (int i = 0; i < 3 * n; i++) out[i] = ldexp(out[i], s);
    return 1;
}

/* h = T(p,q,r) = det3 of the raw rows from the xy minors of the pairs; returns length. */
static int det3(const double *p, const double *q, const double *r, int lqr, const double *mqr,
                int lpr, const double *mpr, int lpq, const double *mpq, double *h)
{
    double t1[8], t2[8], t3[8], s[16];
    int n1 = exp_scale(lqr, mqr, p[2], t1);
    int n2 = exp_scale(lpr, mpr, -q[2], t2);
    int n3 = exp_scale(lpq, mpq, r[2], t3);
    int ns = exp_sum(n1, t1, n2, t2, s);
    int n = exp_sum(ns, s, n3, t3, h);
    return exp_compress(n, h, h); /* keeps the products below short */
}

/* Translated coordinates v[k] = pts[k] - pts[base] (k != base, in order) when all exact. */
static int exact_translate(const double *x, int n, int base, double (*v)[3])
{
    for (int k = 0, r = 0; k < n; k++) {
        if (k == base) continue;
        for (int j = 0; j < 3; j++) {
            double h, t;
            exp_two_sum(x[3 * k + j], -x[3 * base + j], &h, &t);
            if (t != 0) return 0;
            v[r][j] = h;
        }
        r++;
    }
    return 1;
}

static int orient3d_raw(const double *P, const double *Q, const double *R, const double *S)
{
    const double *pt[4] = {P, Q, R, S};
    double m[4][4][4];
    int lm[4][4];
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++)
            lm[i][j] = exp_two_two_diff(pt[i][0], pt[j][1], pt[j][0], pt[i][1], m[i][j]);
    double T[4][24];
    int lt[4];
    /* T[l] = det3 of the three points other than l, in increasing order */
    for (int l = 0; l < 4; l++) {
        int i = l == 0 ? 1 : 0, j = (l <= 1) ? 2 : 1, k = (l <= 2) ? 3 : 2;
        lt[l] = det3(pt[i], pt[j], pt[k], lm[j][k], m[j][k], lm[i][k], m[i][k], lm[i][j],
                     m[i][j], T[l]);
    }
    /* O = T(q,r,s) - T(p,r,s) + T(p,q,s) - T(p,q,r) = T[0] - T[1] + T[2] - T[3] */
    double s1[48], s2[48], o[96];
    exp_negate(lt[1], T[1]);
    exp_negate(lt[3], T[3]);
    int n1 = exp_sum(lt[0], T[0], lt[1], T[1], s1);
    int n2 = exp_sum(lt[2], T[2], lt[3], T[3], s2);
    int n = exp_sum(n1, s1, n2, s2, o);
    return exp_sign(n, o);
}

int pred_orient3d_exp(const double *a, const double *b, const double *c, const double *d,
                      int *sign)
{
    const double *pts[4] = {a, b, c, d};
    double x[12], v[3][3];
    if (!pred_band_scale(pts, 4, x)) return 0;
    if (!exact_translate(x, 4, 0, v)) {
        *sign = orient3d_raw(x, x + 3, x + 6, x + 9);
        return 1;
    }
    /* det = px*m1 + py*m2 + pz*m3 with m1 = qy rz - qz ry, m2 = qz rx - qx rz, m3 = qx ry - qy rx */
    double m[3][4], t[3][8], s[16], h[24];
    int lm[3], lt[3];
    lm[0] = exp_two_two_diff(v[1][1], v[2][2], v[1][2], v[2][1], m[0]);
    lm[1] = exp_two_two_diff(v[1][2], v[2][0], v[1][0], v[2][2], m[1]);
    lm[2] = exp_two_two_diff(v[1][0], v[2][1], v[1][1], v[2][0], m[2]);
    for (int k = 0; k < 3; k++) lt[k] = exp_scale(lm[k], m[k], v[0][k], t[k]);
    int ns = exp_sum(lt[0], t[0], lt[1], t[1], s);
    int n = exp_sum(ns, s, lt[2], t[2], h);
    *sign = exp_sign(n, h);
    return 1;
}

/* |p|^2 as an expansion (<= 6 components) */
static int lift(const double *p, double *h)
{
    double sq[3][2], s[4];
    int l[3];
    for (int j = 0; j < 3; j++) {
        double hi, lo;
        exp_two_prod(p[j], p[j], &hi, &lo);
        l[j] = 0;
        if (lo != 0) sq[j][l[j]++] = lo;
        if (hi != 0) sq[j][l[j]++] = hi;
    }
    int ns = exp_sum(l[0], sq[0], l[1], sq[1], s);
    int n = exp_sum(ns, s, l[2], sq[2], h);
    return exp_compress(n, h, h);
}

static int insphere_translated(double (*v)[3])
{
    const double *A = v[0], *B = v[1], *C = v[2], *D = v[3];
    double ab[4], bc[4], cd[4], da[4], ac[4], bd[4];
    int lab = exp_two_two_diff(A[0], B[1], B[0], A[1], ab);
    int lbc = exp_two_two_diff(B[0], C[1], C[0], B[1], bc);
    int lcd = exp_two_two_diff(C[0], D[1], D[0], C[1], cd);
    int lda = exp_two_two_diff(D[0], A[1], A[0], D[1], da);
    int lac = exp_two_two_diff(A[0], C[1], C[0], A[1], ac);
    int lbd = exp_two_two_diff(B[0], D[1], D[0], B[1], bd);
    /* abc = az*bc - bz*ac + cz*ab, etc.: det3 with the minors passed in its (qr, pr, pq)
     * convention: T(p,q,r) = pz*m(q,r) - qz*m(p,r) + rz*m(p,q). */
    double abc[24], bcd[24], cda[24], dab[24];
    double nbd[4], nac[4];
    for (int i = 0; i < lbd; i++) nbd[i] = -bd[i];
    for (int i = 0; i < lac; i++) nac[i] = -ac[i];
    int labc = det3(A, B, C, lbc, bc, lac, ac, lab, ab, abc);
    int lbcd = det3(B, C, D, lcd, cd, lbd, bd, lbc, bc, bcd);
    /* cda = det[c;d;a] = T(c,d,a) with m(d,a)=da, m(c,a)=-ac, m(c,d)=cd */
    int lcda = det3(C, D, A, lda, da, lac, nac, lcd, cd, cda);
    /* dab = T(d,a,b) with m(a,b)=ab, m(d,b)=-bd, m(d,a)=da */
    int ldab = det3(D, A, B, lab, ab, lbd, nbd, lda, da, dab);
    double w[4][6];
    int lw[4];
    for (int k = 0; k < 4; k++) lw[k] = lift(v[k], w[k]);
    /* det = (cw*dab - dw*abc) + (aw*bcd - bw*cda) */
    static const int wi[4] = {2, 3, 0, 1};
    const double *mi[4] = {dab, abc, bcd, cda};
    const int lmi[4] = {ldab, labc, lbcd, lcda};
    double t[4][288], tmp[288], tmp2[48];
    int lt[4];
    for (int k = 0; k < 4; k++) {
        lt[k] = exp_mul(lmi[k], mi[k], lw[wi[k]], w[wi[k]], t[k], tmp, tmp2);
        if (k & 1) exp_negate(lt[k], t[k]);
    }
    double s1[576], s2[576], h[1152];
    int n1 = exp_sum(lt[0], t[0], lt[1], t[1], s1);
    int n2 = exp_sum(lt[2], t[2], lt[3], t[3], s2);
    int n = exp_sum(n1, s1, n2, s2, h);
    return exp_sign(n, h);
}

int pred_insphere_exp(const double *a, const double *b, const double *c, const double *d,
                      const double *e, int *sign)
{
    const double *pts[5] = {a, b, c, d, e};
    double x[15], v[4][3];
    if (!pred_band_scale(pts, 5, x)) return 0;
    if (!exact_translate(x, 5, 4, v)) return 0; /* GMP is faster there (see file comment) */
    *sign = insphere_translated(v);
    return 1;
}
