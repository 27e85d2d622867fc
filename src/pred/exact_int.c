/* exact_int.c -- exact integer stages: (1) when every coordinate is an integer of small
 * magnitude, the determinants are evaluated exactly in int64_t / __int128; (2) the "wide"
 * stage at the end of the file: the exact integer form of any tuple whose bits span <= 60
 * binades: insphere in limbs of radix 2^62 held in 64/128-bit integers (pred_insphere_wide),
 * orient3d and the coplanar forms in fixed-width 128/192/320-bit two's complement.
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
#include <string.h>

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

/* load_diffs for coordinates known to be integers of magnitude < 2^23 (pred_static.int23): the
 * conversions are exact, no test is needed. */
static inline void load_diffs_known(const double *const *pts, int n, int base, int64_t (*p)[3])
{
    const int64_t o[3] = {(int64_t)pts[base][0], (int64_t)pts[base][1], (int64_t)pts[base][2]};
    for (int k = 0, r = 0; k < n; k++) {
        if (k == base) continue;
        for (int j = 0; j < 3; j++) p[r][j] = (int64_t)pts[k][j] - o[j];
        r++;
    }
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
    return pred_insphere_int_m(a, b, c, d, e, 0, sign, NULL);
}

int pred_insphere_int_m(const double *a, const double *b, const double *c, const double *d,
                        const double *e, int known, int *sign, pred_i128 *mn)
{
    const double *pts[5] = {a, b, c, d, e};
    int64_t p[4][3];
    if (known)
        load_diffs_known(pts, 5, 4, p);
    else if (!load_diffs(pts, 5, 4, 0x1p23, p))
        return 0;
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
        if (det == 0 && mn) mn[0] = abc, mn[1] = bcd, mn[2] = cda, mn[3] = dab;
        return 1;
    }
    i128 abc = (i128)A[2] * bc - (i128)B[2] * ac + (i128)C[2] * ab;
    i128 bcd = (i128)B[2] * cd - (i128)C[2] * bd + (i128)D[2] * bc;
    i128 cda = (i128)C[2] * da + (i128)D[2] * ac + (i128)A[2] * cd;
    i128 dab = (i128)D[2] * ab + (i128)A[2] * bd + (i128)B[2] * da;
    *sign = sign128((cw * dab - dw * abc) + (aw * bcd - bw * cda));
    if (*sign == 0 && mn) mn[0] = abc, mn[1] = bcd, mn[2] = cda, mn[3] = dab;
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

/* ---- wide integer form ------------------------------------------------------------------
 * Any finite double is M * 2^k with M an odd integer (or 0).  With K the smallest k over the
 * tuple, every coordinate is the integer M * 2^(k-K) times the common factor 2^K, and the
 * sign of the homogeneous insphere is that of the integer determinant.  When every such
 * integer is below 2^60 (a tuple whose bits span at most 60 binades, at any scale: points
 * rounded onto a sphere, scaled grids, 2^-1074 or 2^1000 lattices), the evaluation fits fixed
 * widths (insphere's radix-2^62 evaluation has its own bounds below): differences < 2^61 (int64), 2x2 minors < 2^123 and lifts < 3*2^122 (128 bits),
 * 3x3 minors < 3*2^61*2^123 < 2^186 (192-bit two's complement), lift*3x3 < 2^310 and the sum
 * of four < 2^312 (320-bit two's complement).  Every operation below is exact in those widths.
 */
__extension__ typedef unsigned __int128 u128;

typedef struct { uint64_t w[3]; } i192;
typedef struct { uint64_t w[5]; } i320;

static void neg_limbs(uint64_t *w, int n)
{
    uint64_t carry = 1;
    for (int i = 0; i < n; i++) {
        uint64_t v = ~w[i] + carry;
        carry = (carry && v == 0);
        w[i] = v;
    }
}

static void add_limbs(uint64_t *r, const uint64_t *a, int n)
{
    u128 carry = 0;
    for (int i = 0; i < n; i++) {
        u128 t = (u128)r[i] + a[i] + carry;
        r[i] = (uint64_t)t;
        carry = t >> 64;
    }
}

/* r = s * z * m, |z| < 2^61, |m| < 2^123, s = +-1 */
static i192 mul_z_minor(int64_t z, i128 m, int s)
{
    i192 r;
    int neg = (z < 0) != (m < 0);
    if (s < 0) neg = !neg;
    uint64_t az = (uint64_t)(z < 0 ? -z : z);
    u128 am = (u128)(m < 0 ? -m : m);
    u128 p0 = (u128)az * (uint64_t)am, p1 = (u128)az * (uint64_t)(am >> 64);
    u128 t = (p0 >> 64) + (uint64_t)p1;
    r.w[0] = (uint64_t)p0;
    r.w[1] = (uint64_t)t;
    r.w[2] = (uint64_t)(t >> 64) + (uint64_t)(p1 >> 64);
    if (neg) neg_limbs(r.w, 3);
    return r;
}

/* r = s * lift * d, lift < 2^124 unsigned, d signed 192-bit, s = +-1 */
static i320 mul_lift_det3(u128 lift, i192 d, int s)
{
    i320 r = {{0, 0, 0, 0, 0}};
    int neg = (d.w[2] >> 63) != 0;
    if (neg) neg_limbs(d.w, 3);
    if (s < 0) neg = !neg;
    const uint64_t l[2] = {(uint64_t)lift, (uint64_t)(lift >> 64)};
    for (int i = 0; i < 2; i++) {
        u128 carry = 0;
        for (int j = 0; j < 3; j++) {
            u128 t = (u128)l[i] * d.w[j] + r.w[i + j] + carry;
            r.w[i + j] = (uint64_t)t;
            carry = t >> 64;
        }
        r.w[i + 3] = (uint64_t)carry;
    }
    if (neg) neg_limbs(r.w, 5);
    return r;
}

/* integer form of n coordinates below 2^60 after removing the common power of two: the
 * general loop (any finite doubles, subnormals included) */
static int wide_form_general(const double *const *pts, int n, int64_t (*q)[3])
{
    int64_t m[15];
    int k[15], K = 1 << 20;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) {
            uint64_t u;
            memcpy(&u, &pts[i][j], sizeof u);
            int be = (int)((u >> 52) & 0x7ff);
            uint64_t mant = (u & ((UINT64_C(1) << 52) - 1)) | (be ? UINT64_C(1) << 52 : 0);
            int idx = 3 * i + j;
            if (be == 0x7ff) return 0; /* not finite */
            if (mant == 0) {
                m[idx] = 0;
                k[idx] = 0;
                continue;
            }
            int tz = __builtin_ctzll(mant);
            mant >>= tz;
            k[idx] = (be ? be - 1075 : -1074) + tz; /* x = mant * 2^k, mant odd */
            m[idx] = (u >> 63) ? -(int64_t)mant : (int64_t)mant;
            if (k[idx] < K) K = k[idx];
        }
    for (int idx = 0; idx < 3 * n; idx++) {
        if (m[idx] == 0) {
            q[idx / 3][idx % 3] = 0;
            continue;
        }
        int bits = 64 - __builtin_clzll((uint64_t)(m[idx] < 0 ? -m[idx] : m[idx]));
        int sh = k[idx] - K;
        if (sh > 60 || bits + sh > 60) return 0;
        q[idx / 3][idx % 3] = m[idx] * ((int64_t)1 << sh);
    }
    return 1;
}

/* The same integer form, fast: with 2^E <= max|x| < 2^(E+1) the form exists iff every
 * coordinate is an integer multiple of 2^(E-59), i.e. iff every x * 2^(59-E) is an integer
 * (then below 2^60 in magnitude).  When 2^(59-E) is a normal double, each product is exact
 * unless it underflows, and an underflowed product is below 1: it is an integer only when it
 * is 0, which the test (i != 0 || x == 0) rejects for x != 0.  So an accepted product is the
 * exact x * 2^(59-E), and the form is the general one's times a power of two (the signs of
 * the homogeneous predicates do not change).  It accepts exactly the tuples
 * wide_form_general accepts (both: every coordinate a multiple of 2^(E-59)); a max below
 * 2^-964 or subnormal (scale not a normal double) goes to the general loop. */
static int wide_form(const double *const *pts, int n, int64_t (*q)[3])
{
    uint64_t mx = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) {
            uint64_t u;
            memcpy(&u, &pts[i][j], sizeof u);
            u &= ~(UINT64_C(1) << 63);
            mx = u > mx ? u : mx;
        }
    if (mx >= UINT64_C(0x7ff0000000000000)) return 0; /* inf or NaN */
    const int be = (int)(mx >> 52);                     /* 0: max is 0 or subnormal */
    const int s = 59 - (be - 1023);                     /* E = be - 1023 */
    if (be == 0 || s > 1023) return wide_form_general(pts, n, q);
    const uint64_t fb = (uint64_t)(s + 1023) << 52;     /* s >= 59 - 1023 > -1022 */
    double f;
    memcpy(&f, &fb, sizeof f);
    int ok = 1;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) {
            const double x = pts[i][j], y = x * f;     /* |y| < 2^60 */
            const int64_t v = (int64_t)y;
            ok &= ((double)v == y) & ((v != 0) | (x == 0));
            q[i][j] = v;
        }
    return ok;
}

/* insphere on the integer form, in limbs of radix 2^62 held in signed 64/128-bit integers
 * (no carries inside a product: every partial product and every column sum is bounded below
 * 2^127).  Bounds (|q| < 2^60):
 *   differences p = q - q_e:        |p| < 2^61 (int64)
 *   2x2 minors m = ab, ...:          |m| < 2^123, split m = mh 2^62 + ml, ml in [0, 2^62),
 *                                    |mh| <= 2^61
 *   3x3 minor, e.g. az bc - bz ac + cz ab = Sh 2^62 + Sl with Sh = sum z mh (|.| < 3 2^122)
 *                                    and Sl = sum z ml (|.| < 3 2^123); normalized to
 *                                    a2 2^124 + a1 2^62 + a0, a0, a1 in [0, 2^62),
 *                                    |a2| <= 3 2^60 + 1
 *   lifts w = |p|^2 < 3 2^122 = lh 2^62 + ll, ll in [0, 2^62), lh < 3 2^60
 *   det = sum of four +-w*minor: columns of radix 2^62
 *     c0 = sum +-ll a0                  |.| < 4 2^124 = 2^126
 *     c1 = sum +-(ll a1 + lh a0)        |.| < 4 (2^124 + 3 2^122) = 7 2^124
 *     c2 = sum +-(ll a2 + lh a1)        |.| < 4 (3 2^122 + 2^62 + 3 2^122) < 7 2^124
 *     c3 = sum +-lh a2                  |.| < 4 (3 2^60)(3 2^60 + 1) < 2^126
 *   and carrying c_k >> 62 (|.| < 2^65) into c_(k+1) stays below 2^127.  Then det =
 *   c3' 2^186 + c2' 2^124 + c1' 2^62 + c0' with c0', c1', c2' in [0, 2^62): its sign is c3''s,
 *   or 0 / +1 when c3' = 0.  ">> 62" on a negative signed value is the arithmetic shift (GCC
 *   and Clang define it so), i.e. floor division: v = (v >> 62) 2^62 + (v & (2^62 - 1)). */
#define R62 ((INT64_C(1) << 62) - 1)

typedef struct { int64_t a0, a1, a2; } r62x3; /* a2 2^124 + a1 2^62 + a0 */

/* z1 m1 + z2 m2 + z3 m3 for 2x2 minors given as (mh, ml) pairs */
static inline r62x3 minor3(int64_t z1, const int64_t *m1, int64_t z2, const int64_t *m2,
                           int64_t z3, const int64_t *m3)
{
    const i128 sh = (i128)z1 * m1[0] + (i128)z2 * m2[0] + (i128)z3 * m3[0];
    const i128 sl = (i128)z1 * m1[1] + (i128)z2 * m2[1] + (i128)z3 * m3[1];
    const i128 t = sh + (sl >> 62);
    r62x3 r = {(int64_t)(sl & R62), (int64_t)(t & R62), (int64_t)(t >> 62)};
    return r;
}

static inline void split62(i128 v, int64_t *hl)
{
    hl[0] = (int64_t)(v >> 62);
    hl[1] = (int64_t)(v & R62);
}

/* c[0..3] += s * w * a (columns as above) */
static inline void add_lift_minor(i128 *c, const int64_t *w, r62x3 a, int s)
{
    const int64_t lh = s * w[0], ll = s * w[1];
    c[0] += (i128)ll * a.a0;
    c[1] += (i128)ll * a.a1 + (i128)lh * a.a0;
    c[2] += (i128)ll * a.a2 + (i128)lh * a.a1;
    c[3] += (i128)lh * a.a2;
}

int pred_insphere_wide(const double *a, const double *b, const double *c, const double *d,
                       const double *e, int *sign)
{
    const double *pts[5] = {a, b, c, d, e};
    int64_t q[5][3], p[4][3];
    if (!wide_form(pts, 5, q)) return 0;
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) p[k][j] = q[k][j] - q[4][j];
    const int64_t *A = p[0], *B = p[1], *C = p[2], *D = p[3];
    int64_t ab[2], bc[2], cd[2], da[2], ac[2], bd[2], w[4][2];
    split62((i128)A[0] * B[1] - (i128)B[0] * A[1], ab);
    split62((i128)B[0] * C[1] - (i128)C[0] * B[1], bc);
    split62((i128)C[0] * D[1] - (i128)D[0] * C[1], cd);
    split62((i128)D[0] * A[1] - (i128)A[0] * D[1], da);
    split62((i128)A[0] * C[1] - (i128)C[0] * A[1], ac);
    split62((i128)B[0] * D[1] - (i128)D[0] * B[1], bd);
    for (int k = 0; k < 4; k++)
        split62((i128)p[k][0] * p[k][0] + (i128)p[k][1] * p[k][1] + (i128)p[k][2] * p[k][2],
                w[k]);
    /* same cofactors as the filter: abc = az bc - bz ac + cz ab, ... */
    const r62x3 abc = minor3(A[2], bc, -B[2], ac, C[2], ab);
    const r62x3 bcd = minor3(B[2], cd, -C[2], bd, D[2], bc);
    const r62x3 cda = minor3(C[2], da, D[2], ac, A[2], cd);
    const r62x3 dab = minor3(D[2], ab, A[2], bd, B[2], da);
    /* det = (cw*dab - dw*abc) + (aw*bcd - bw*cda) */
    i128 col[4] = {0, 0, 0, 0};
    add_lift_minor(col, w[2], dab, 1);
    add_lift_minor(col, w[3], abc, -1);
    add_lift_minor(col, w[0], bcd, 1);
    add_lift_minor(col, w[1], cda, -1);
    col[1] += col[0] >> 62;
    col[2] += col[1] >> 62;
    col[3] += col[2] >> 62;
    if (col[3] != 0) {
        *sign = col[3] > 0 ? 1 : -1;
    } else {
        *sign = ((col[0] & R62) | (col[1] & R62) | (col[2] & R62)) != 0;
    }
    return 1;
}

/* orient3d on the same integer form: differences < 2^61, minors < 2^123, |det| < 3*2^184. */
int pred_orient3d_wide(const double *a, const double *b, const double *c, const double *d,
                       int *sign)
{
    const double *pts[4] = {a, b, c, d};
    int64_t q[4][3], p[3][3];
    if (!wide_form(pts, 4, q)) return 0;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) p[k][j] = q[k + 1][j] - q[0][j];
    /* det = px*m1 + py*m2 + pz*m3 as in the filter */
    i128 m1 = (i128)p[1][1] * p[2][2] - (i128)p[1][2] * p[2][1];
    i128 m2 = (i128)p[1][2] * p[2][0] - (i128)p[1][0] * p[2][2];
    i128 m3 = (i128)p[1][0] * p[2][1] - (i128)p[1][1] * p[2][0];
    i192 r = mul_z_minor(p[0][0], m1, 1), t;
    t = mul_z_minor(p[0][1], m2, 1), add_limbs(r.w, t.w, 3);
    t = mul_z_minor(p[0][2], m3, 1), add_limbs(r.w, t.w, 3);
    if (r.w[2] >> 63)
        *sign = -1;
    else
        *sign = (r.w[0] | r.w[1] | r.w[2]) != 0;
    return 1;
}

/* ---- the coplanar predicates on the wide integer form -------------------------------------
 * (sos.c: orient2d in a coordinate plane and the lifted 2D determinant of the coplanar
 * in-circle.)  Same integer form as above (common power of two removed, every integer below
 * 2^60): orient2d: differences < 2^61, products < 2^122, their difference < 2^123 (__int128).
 * lifted2d: differences < 2^61, 2x2 minors < 2^123 (__int128), lifts (three squares) < 3*2^122
 * < 2^124 (unsigned __int128), lift * minor < 2^247 and the sum of three < 2^249 (320-bit
 * two's complement, mul_lift_det3).  Every operation is exact in those widths.  Without these,
 * tuples with non-integer coordinates in a coordinate plane would go to GMP, where plane +
 * apex inputs would spend most of their time (NOTES.md E11). */
int pred_orient2d_wide(const double *a, const double *b, const double *c, int u, int w,
                       int *sign)
{
    const double *pts[3] = {a, b, c};
    int64_t q[3][3];
    if (!wide_form(pts, 3, q)) return 0;
    const i128 det = (i128)(q[1][u] - q[0][u]) * (q[2][w] - q[0][w]) -
                     (i128)(q[1][w] - q[0][w]) * (q[2][u] - q[0][u]);
    *sign = sign128(det);
    return 1;
}

int pred_lifted2d_wide(const double *a, const double *b, const double *c, const double *e,
                       int u, int w, int *sign)
{
    const double *pts[4] = {a, b, c, e};
    int64_t q[4][3], p[3][3];
    if (!wide_form(pts, 4, q)) return 0;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) p[k][j] = q[k][j] - q[3][j];
    i320 r = {{0, 0, 0, 0, 0}};
    for (int k = 0; k < 3; k++) {
        const int64_t *x = p[(k + 1) % 3], *y = p[(k + 2) % 3];
        const i128 minor = (i128)x[u] * y[w] - (i128)y[u] * x[w];
        const u128 lift = (u128)((i128)p[k][0] * p[k][0]) + (u128)((i128)p[k][1] * p[k][1]) +
                          (u128)((i128)p[k][2] * p[k][2]);
        i192 m; /* minor sign-extended to 192 bits */
        m.w[0] = (uint64_t)(u128)minor;
        m.w[1] = (uint64_t)((u128)minor >> 64);
        m.w[2] = minor < 0 ? UINT64_MAX : 0;
        const i320 t = mul_lift_det3(lift, m, 1);
        add_limbs(r.w, t.w, 5);
    }
    if (r.w[4] >> 63)
        *sign = -1;
    else
        *sign = (r.w[0] | r.w[1] | r.w[2] | r.w[3] | r.w[4]) != 0;
    return 1;
}

/* ---- the 122-bit integer form (insphere) --------------------------------------------------
 * Tuples whose bits span 61 to 122 binades (points rounded onto a sphere with a coordinate
 * near 0: its ulp is far below the others') used to go to GMP, whose allocations made them
 * ~25 times dearer than the 60-bit form.  Here the same integer form (common power of two
 * removed), every integer below 2^122 (__int128), in short digit vectors on the stack:
 *   a dv is sum d[i] 2^(60 i), d[i] in [0, 2^60) below the top digit, the top digit signed
 *   with |d[n-1]| <= 2^60 (dv_norm).  A sum of products (dv_dot) adds, per column, at most
 *   sum over its products of min(na, nb) <= 4 * 5 = 20 digit products of magnitude <= 2^120:
 *   below 2^125 (__int128), normalized once.
 * Sizes: differences < 2^123 (3 digits), 2x2 minors < 2^247 (5), 3x3 minors < 3 2^370 (7),
 * lifts < 3 2^246 (5), det < 2^621 (11 digits; with carries <= DV_MAX).  ">> 60" on a
 * negative __int128 is the arithmetic shift (floor), as for the 60-bit form above. */
#define DV_MAX 16
#define R60 ((INT64_C(1) << 60) - 1)
typedef struct { int n; int64_t d[DV_MAX]; } dv;

/* r = sum c[k] 2^(60 k), k < n, normalized (|c[k]| < 2^126). */
static void dv_norm(const i128 *c, int n, dv *r)
{
    i128 carry = 0;
    int k = 0;
    for (; k < n; k++) {
        const i128 v = c[k] + carry;
        r->d[k] = (int64_t)(v & R60);
        carry = v >> 60;                    /* floor: v = carry 2^60 + d */
    }
    while (carry != 0 && carry != -1) {
        r->d[k++] = (int64_t)(carry & R60);
        carry >>= 60;
    }
    if (carry == -1) r->d[k - 1] -= (int64_t)1 << 60;  /* the top digit takes the -2^(60k) */
    while (k > 1 && r->d[k - 1] == 0) k--;
    r->n = k;
}

/* r = sum of s[i] x[i] y[i], i < np (np <= 4) */
static void dv_dot(const dv *const *x, const dv *const *y, const int *s, int np, dv *r)
{
    i128 c[DV_MAX];
    int n = 0;
    for (int i = 0; i < np; i++)
        if (x[i]->n + y[i]->n - 1 > n) n = x[i]->n + y[i]->n - 1;
    for (int k = 0; k < n; k++) c[k] = 0;
    for (int i = 0; i < np; i++) {
        const dv *a = x[i], *b = y[i];
        for (int j = 0; j < a->n; j++) {
            const i128 aj = s[i] < 0 ? -(i128)a->d[j] : (i128)a->d[j];
            for (int l = 0; l < b->n; l++) c[j + l] += aj * b->d[l];
        }
    }
    dv_norm(c, n, r);
}

static int dv_sign(const dv *a)
{
    if (a->n > 1 || a->d[0] != 0) return a->d[a->n - 1] < 0 ? -1 : 1;
    return 0;  /* lower digits are >= 0, so a nonzero value has a nonzero top of its sign */
}

/* integer form of n points with every integer below 2^122, as __int128 */
static int wide_form_122(const double *const *pts, int n, i128 (*q)[3])
{
    int64_t m[15];
    int k[15], K = 1 << 20;
    for (int idx = 0; idx < 3 * n; idx++) {
        uint64_t u;
        memcpy(&u, &pts[idx / 3][idx % 3], sizeof u);
        const int be = (int)((u >> 52) & 0x7ff);
        uint64_t mant = (u & ((UINT64_C(1) << 52) - 1)) | (be ? UINT64_C(1) << 52 : 0);
        if (be == 0x7ff) return 0;
        m[idx] = 0;
        k[idx] = 0;
        if (mant == 0) continue;
        const int tz = __builtin_ctzll(mant);
        mant >>= tz;
        k[idx] = (be ? be - 1075 : -1074) + tz;
        m[idx] = (u >> 63) ? -(int64_t)mant : (int64_t)mant;
        if (k[idx] < K) K = k[idx];
    }
    for (int idx = 0; idx < 3 * n; idx++) {
        i128 v = 0;
        if (m[idx] != 0) {
            const int bits = 64 - __builtin_clzll((uint64_t)(m[idx] < 0 ? -m[idx] : m[idx]));
            const int sh = k[idx] - K;
            if (sh > 122 || bits + sh > 122) return 0;
            v = (i128)m[idx] * ((i128)1 << sh);
        }
        q[idx / 3][idx % 3] = v;
    }
    return 1;
}

/* xy minor u_x v_y - v_x u_y */
static void dv_minor(const dv *u, const dv *v, dv *r)
{
    const dv *x[2] = {&u[0], &v[0]}, *y[2] = {&v[1], &u[1]};
    static const int s[2] = {1, -1};
    dv_dot(x, y, s, 2, r);
}

/* z1 m1 + s2 z2 m2 + z3 m3 */
static void dv_det3(const dv *z1, const dv *m1, const dv *z2, const dv *m2, int s2,
                    const dv *z3, const dv *m3, dv *r)
{
    const dv *x[3] = {z1, z2, z3}, *y[3] = {m1, m2, m3};
    const int s[3] = {1, s2, 1};
    dv_dot(x, y, s, 3, r);
}

int pred_insphere_wide122(const double *a, const double *b, const double *c, const double *d,
                          const double *e, int *sign)
{
    const double *pts[5] = {a, b, c, d, e};
    i128 q[5][3];
    if (!wide_form_122(pts, 5, q)) return 0;
    dv p[4][3];
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) {
            const i128 v = q[k][j] - q[4][j];  /* < 2^123 */
            dv_norm(&v, 1, &p[k][j]);
        }
    const dv *A = p[0], *B = p[1], *C = p[2], *D = p[3];
    dv ab, bc, cd, da, ac, bd, abc, bcd, cda, dab, w[4], det;
    dv_minor(A, B, &ab), dv_minor(B, C, &bc), dv_minor(C, D, &cd);
    dv_minor(D, A, &da), dv_minor(A, C, &ac), dv_minor(B, D, &bd);
    static const int plus[4] = {1, 1, 1, 1};
    for (int k = 0; k < 4; k++) {
        const dv *x[3] = {&p[k][0], &p[k][1], &p[k][2]};
        dv_dot(x, x, plus, 3, &w[k]);  /* the lift |p|^2 */
    }
    /* the filter's cofactors: abc = az bc - bz ac + cz ab, ... */
    dv_det3(&A[2], &bc, &B[2], &ac, -1, &C[2], &ab, &abc);
    dv_det3(&B[2], &cd, &C[2], &bd, -1, &D[2], &bc, &bcd);
    dv_det3(&C[2], &da, &D[2], &ac, 1, &A[2], &cd, &cda);
    dv_det3(&D[2], &ab, &A[2], &bd, 1, &B[2], &da, &dab);
    /* det = (cw*dab - dw*abc) + (aw*bcd - bw*cda) */
    const dv *x[4] = {&w[2], &w[3], &w[0], &w[1]}, *y[4] = {&dab, &abc, &bcd, &cda};
    static const int s[4] = {1, -1, 1, -1};
    dv_dot(x, y, s, 4, &det);
    *sign = dv_sign(&det);
    return 1;
}
