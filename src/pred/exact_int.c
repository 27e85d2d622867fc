/* exact_int.c -- exact small-integer stage: when every coordinate is an integer of small
 * magnitude, the determinants are evaluated exactly in int64_t / __int128.
 *
 * This is the common exact case on grid inputs (on a 100^3 grid almost every insphere is
 * exactly 0), so it must be cheap: one range+integrality test per coordinate, then the
 * determinant in integers.  Bounds (D = bound on |translated coordinate| = 2 * coordinate bound):
 *   orient3d  |x| < 2^40, D = 2^41: 2x2 minors < 2 D^2 = 2^83, terms < 2^124, |det| < 6 D^3 <
 *             2^125.6 < 2^127.  int64 only when D <= 2^20: minors < 2^41, |det| < 2^62.6.
 *   insphere  |x| < 2^23, D = 2^24: 2x2 minors < 2D^2 = 2^49 (int64), 3x3 minors < 6D^3 =
 *             2^74.6, lifts < 3D^2 = 2^49.6 (int64), terms < 18 D^5, |det| < 72 D^5 = 2^126.2.
 *             int64 only when D <= 2^11: 3x3 < 2^35.6, lifts < 2^23.6, |det| < 72*2^55 = 2^61.2.
 *   orient2d  |x| < 2^40: |det| < 2 D^2 = 2^83 (__int128).
 *   lifted2d  |x| < 2^23: 2x2 minors < 2^49, lifts < 2^49.6, |det| < 3*2^98.6 < 2^101.
 * All evaluation orders below equal the determinant exactly since no operation overflows.
 */
#include "pred_internal.h"

#include <stdint.h>

__extension__ typedef __int128 i128; /* GCC/Clang extension on 64-bit targets */

/* coordinate -> int64 when it is an integer of magnitude < lim (written so that NaN fails) */
static inline int to_int(double x, double lim, int64_t *out)
{
    if (!(x > -lim && x < lim)) return 0;
    int64_t i = (int64_t)x;
    *out = i;
    return (double)i == x;
}

static inline int sign128(i128 v) { return (v > 0) - (v < 0); }
static inline int64_t iabs64(int64_t v) { return v < 0 ? -v : v; }

/* p[k] = coordinates of pts[k] minus those of pts[base]; returns 0 when not all integral. */
static int load_diffs(const double *const *pts, int n, int base, double lim, int64_t (*p)[3])
{
    int64_t o[3];
    for (int j = 0; j < 3; j++)
        if (!to_int(pts[base][j], lim, &o[j])) return 0;
    for (int k = 0, r = 0; k < n; k++) {
        if (k == base) continue;
        for (int j = 0; j < 3; j++) {
            int64_t v;
            if (!to_int(pts[k][j], lim, &v)) return 0;
            p[r][j] = v - o[j];
        }
        r++;
    }
    return 1;
}

int pred_orient3d_int(const double *a, const double *b, const double *c, const double *d,
                      int *sign)
{
    const double *pts[4] = {a, b, c, d};
    int64_t p[3][3];
    if (!load_diffs(pts, 4, 0, 0x1p40, p)) return 0;
    int64_t m = 0;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) m |= iabs64(p[k][j]);
    if (m <= (INT64_C(1) << 20)) {
        int64_t m1 = p[1][1] * p[2][2] - p[1][2] * p[2][1];
        int64_t m2 = p[1][2] * p[2][0] - p[1][0] * p[2][2];
        int64_t m3 = p[1][0] * p[2][1] - p[1][1] * p[2][0];
        int64_t det = p[0][0] * m1 + p[0][1] * m2 + p[0][2] * m3;
        *sign = (det > 0) - (det < 0);
        return 1;
    }
    i128 m1 = (i128)p[1][1] * p[2][2] - (i128)p[1][2] * p[2][1];
    i128 m2 = (i128)p[1][2] * p[2][0] - (i128)p[1][0] * p[2][2];
    i128 m3 = (i128)p[1][0] * p[2][1] - (i128)p[1][1] * p[2][0];
    *sign = sign128(p[0][0] * m1 + p[0][1] * m2 + p[0][2] * m3);
    return 1;
}

int pred_insphere_int(const double *a, const double *b, const double *c, const double *d,
                      const double *e, int *sign)
{
    const double *pts[5] = {a, b, c, d, e};
    int64_t p[4][3];
    if (!load_diffs(pts, 5, 4, 0x1p23, p)) return 0;
    int64_t m = 0;
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) m |= iabs64(p[k][j]);
    const int64_t *A = p[0], *B = p[1], *C = p[2], *D = p[3];
    /* 2x2 xy minors: |.| < 2^49 in both branches */
    int64_t ab = A[0] * B[1] - B[0] * A[1], bc = B[0] * C[1] - C[0] * B[1];
    int64_t cd = C[0] * D[1] - D[0] * C[1], da = D[0] * A[1] - A[0] * D[1];
    int64_t ac = A[0] * C[1] - C[0] * A[1], bd = B[0] * D[1] - D[0] * B[1];
    int64_t aw = A[0] * A[0] + A[1] * A[1] + A[2] * A[2];
    int64_t bw = B[0] * B[0] + B[1] * B[1] + B[2] * B[2];
    int64_t cw = C[0] * C[0] + C[1] * C[1] + C[2] * C[2];
    int64_t dw = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
    if (m <= (INT64_C(1) << 11)) {
        int64_t abc = A[2] * bc - B[2] * ac + C[2] * ab;
        int64_t bcd = B[2] * cd - C[2] * bd + D[2] * bc;
        int64_t cda = C[2] * da + D[2] * ac + A[2] * cd;
        int64_t dab = D[2] * ab + A[2] * bd + B[2] * da;
        int64_t det = (cw * dab - dw * abc) + (aw * bcd - bw * cda);
        *sign = (det > 0) - (det < 0);
        return 1;
    }
    i128 abc = (i128)A[2] * bc - (i128)B[2] * ac + (i128)C[2] * ab;
    i128 bcd = (i128)B[2] * cd - (i128)C[2] * bd + (i128)D[2] * bc;
    i128 cda = (i128)C[2] * da + (i128)D[2] * ac + (i128)A[2] * cd;
    i128 dab = (i128)D[2] * ab + (i128)A[2] * bd + (i128)B[2] * da;
    *sign = sign128((cw * dab - dw * abc) + (aw * bcd - bw * cda));
    return 1;
}

int pred_orient2d_int(const double *a, const double *b, const double *c, int u, int w,
                      int *sign)
{
    int64_t v[3][2];
    const double *pts[3] = {a, b, c};
    for (int k = 0; k < 3; k++)
        if (!to_int(pts[k][u], 0x1p40, &v[k][0]) || !to_int(pts[k][w], 0x1p40, &v[k][1]))
            return 0;
    i128 det = (i128)(v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) -
               (i128)(v[1][1] - v[0][1]) * (v[2][0] - v[0][0]);
    *sign = sign128(det);
    return 1;
}

int pred_lifted2d_int(const double *a, const double *b, const double *c, const double *e,
                      int u, int w, int *sign)
{
    const double *pts[4] = {a, b, c, e};
    int64_t p[3][3];
    if (!load_diffs(pts, 4, 3, 0x1p23, p)) return 0;
    i128 det = 0;
    for (int k = 0; k < 3; k++) {
        const int64_t *q = p[(k + 1) % 3], *r = p[(k + 2) % 3];
        int64_t minor = q[u] * r[w] - r[u] * q[w];
        int64_t lift = p[k][0] * p[k][0] + p[k][1] * p[k][1] + p[k][2] * p[k][2];
        det += (i128)lift * minor;
    }
    *sign = sign128(det);
    return 1;
}
