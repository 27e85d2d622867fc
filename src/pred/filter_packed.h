/* filter_packed.h -- the kernel's packed evaluations of filter.h's insphere filter: two lanes
 * with SSE2 (x86-64's baseline), four with AVX2 (the translation units compiled with it,
 * kernel/insert_avx2.c), and the semi-static-first order (kernel/conflict.h
 * km_filter_order).  Each computes the values of filter.h's scalar text, in its FIXED
 * evaluation order, bit for bit (proofs/filters.md section 13); that text stays in filter.h,
 * where proofs/gappa_gen.py reads it.  Included by filter.h. */
#ifndef GTET_PRED_FILTER_PACKED_H
#define GTET_PRED_FILTER_PACKED_H
#include "filter.h"

#if defined(__SSE2__)
#include <emmintrin.h>
/* pred_insphere_filter with two lanes at a time (SSE2, x86-64's baseline): the same answer and
 * the same record, bit for bit.  Every value is computed by exactly the operation, on exactly
 * the operands, of the FIXED evaluation order above; only which values share a register
 * changes (lane-wise IEEE operations round each lane as the scalar operation would).  Two
 * rewritings are used, both exact identities of IEEE arithmetic: x + y*z is computed as
 * x - (-y)*z (negation and x - w = x + (-w) are exact), so that the lanes of a pair all
 * subtract; and a product's operands may be swapped.  The pairs:
 *     (ab, cd) = (ax, cx)*(by, dy) - (bx, dx)*(ay, cy)
 *     (bc, da) = (bx, dx)*(cy, ay) - (cx, ax)*(by, dy)
 *     (ac, bd) = (ax, bx)*(cy, dy) - (cx, dx)*(ay, by)
 *     (abc, cda) = ((az, cz)*(bc, da) - (bz, -dz)*(ac, ac)) + (cz, az)*(ab, cd)
 *     (bcd, dab) = ((bz, dz)*(cd, ab) - (cz, -az)*(bd, bd)) + (dz, bz)*(bc, da)
 *     (aw, bw) = ((ax, bx)^2 + (ay, by)^2) + (az, bz)^2, (cw, dw) likewise
 *     det = lane 0 + lane 1 of (cw, aw)*(dab, bcd) - (dw, bw)*(abc, cda)
 * (x^2 is x*x; proofs/filters.md section 13.)  When the static test does not decide, the
 * scalar filter's remaining statements run on the lanes' values (pred_insphere_packed_rest_).
 * ~2/3 of the scalar form's instructions (NOTES.md E140); tests/test_pred_packed_filter.c
 * compares det~, the answers and the records with the scalar filter's. */
#define PRED_INSPHERE_PACKED 1
static inline __m128d pred_swap_(__m128d x) { return _mm_shuffle_pd(x, x, 1); }

/* The lanes an undecided call's rest needs: the translated points and the 3x3 minors. */
typedef struct pred_is_lanes_ {
    __m128d A, B, C, D, Z1, Z2, abc_cda, bcd_dab;
} pred_is_lanes_;

static inline double pred_insphere_lanes_(const double *a, const double *b, const double *c,
                                          const double *d, const double *e, pred_is_lanes_ *L)
{
    const __m128d exy = _mm_loadu_pd(e), ez = _mm_set1_pd(e[2]);
    const __m128d A = _mm_sub_pd(_mm_loadu_pd(a), exy);   /* (ax, ay) */
    const __m128d B = _mm_sub_pd(_mm_loadu_pd(b), exy);
    const __m128d C = _mm_sub_pd(_mm_loadu_pd(c), exy);
    const __m128d D = _mm_sub_pd(_mm_loadu_pd(d), exy);
    const __m128d Z1 = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(a + 2), b + 2), ez); /* (az, bz) */
    const __m128d Z2 = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(c + 2), d + 2), ez); /* (cz, dz) */
    const __m128d X1 = _mm_unpacklo_pd(A, C), Y1 = _mm_unpackhi_pd(A, C); /* (ax,cx) (ay,cy) */
    const __m128d X2 = _mm_unpacklo_pd(B, D), Y2 = _mm_unpackhi_pd(B, D); /* (bx,dx) (by,dy) */
    const __m128d XA = _mm_unpacklo_pd(A, B), YA = _mm_unpackhi_pd(A, B); /* (ax,bx) (ay,by) */
    const __m128d XC = _mm_unpacklo_pd(C, D), YC = _mm_unpackhi_pd(C, D); /* (cx,dx) (cy,dy) */
    const __m128d ab_cd = _mm_sub_pd(_mm_mul_pd(X1, Y2), _mm_mul_pd(X2, Y1));
    const __m128d bc_da = _mm_sub_pd(_mm_mul_pd(X2, pred_swap_(Y1)),
                                     _mm_mul_pd(pred_swap_(X1), Y2));
    const __m128d ac_bd = _mm_sub_pd(_mm_mul_pd(XA, YC), _mm_mul_pd(XC, YA));
    const __m128d neg_hi = _mm_set_pd(-0.0, 0.0);          /* flips lane 1's sign */
    const __m128d azcz = _mm_unpacklo_pd(Z1, Z2), bzdz = _mm_unpackhi_pd(Z1, Z2);
    const __m128d czaz = pred_swap_(azcz), dzbz = pred_swap_(bzdz);
    const __m128d abc_cda = _mm_add_pd(
        _mm_sub_pd(_mm_mul_pd(azcz, bc_da),
                   _mm_mul_pd(_mm_xor_pd(bzdz, neg_hi), _mm_unpacklo_pd(ac_bd, ac_bd))),
        _mm_mul_pd(czaz, ab_cd));
    const __m128d bcd_dab = _mm_add_pd(
        _mm_sub_pd(_mm_mul_pd(bzdz, pred_swap_(ab_cd)),
                   _mm_mul_pd(_mm_xor_pd(czaz, neg_hi), _mm_unpackhi_pd(ac_bd, ac_bd))),
        _mm_mul_pd(dzbz, bc_da));
    const __m128d awbw = _mm_add_pd(_mm_add_pd(_mm_mul_pd(XA, XA), _mm_mul_pd(YA, YA)),
                                    _mm_mul_pd(Z1, Z1));
    const __m128d cwdw = _mm_add_pd(_mm_add_pd(_mm_mul_pd(XC, XC), _mm_mul_pd(YC, YC)),
                                    _mm_mul_pd(Z2, Z2));
    const __m128d halves = _mm_sub_pd(_mm_mul_pd(_mm_unpacklo_pd(cwdw, awbw), pred_swap_(bcd_dab)),
                                      _mm_mul_pd(_mm_unpackhi_pd(cwdw, awbw), abc_cda));
    *L = (pred_is_lanes_){A, B, C, D, Z1, Z2, abc_cda, bcd_dab};
    return _mm_cvtsd_f64(_mm_add_sd(halves, _mm_unpackhi_pd(halves, halves)));
}

/* det~ alone (the test's handle on the lanes) */
static inline double pred_insphere_det_packed_(const double *a, const double *b,
                                               const double *c, const double *d,
                                               const double *e)
{
    pred_is_lanes_ L;
    return pred_insphere_lanes_(a, b, c, d, e, &L);
}

/* The static test failed: the rest of pred_insphere_filter (from `if (seps == 0)` on) on the
 * lanes' values, so that an undecided call does not pay for a second evaluation (the sphere,
 * the paraboloid and surface samples, where the static bound often fails).  The same values
 * as the scalar text: X, Y, Z, lo and M are maxima and minima of absolute values, which are
 * exact, so their grouping does not matter as long as no translation is NaN (a tuple of
 * finite points has none: a difference of finite doubles is finite or infinite); the
 * absolute values are taken by clearing the sign bit (andpd, as fabs does) and the maxima by
 * maxpd, which returns the larger of two non-NaN values, either one when they are equal (the
 * same bits: no -0.0 is left).  eps is the scalar product chain in the FIXED order.  The
 * minors are stored only for an undecided record.  tests/test_pred_packed_filter.c compares
 * the answers and the records byte for byte with the scalar filter's.
 * Repeated rather than shared with pred_insphere_filter: proofs/check builds the Gappa model
 * of the certified bound from that function's own text, which a helper would take apart. */
/* the minors abc, bcd, cda, dab from the lanes (abc, cda) and (bcd, dab) */
static inline void pred_insphere_packed_minors_(const pred_is_lanes_ *L, double *minors)
{
    double t[4];
    _mm_storeu_pd(t, L->abc_cda);
    _mm_storeu_pd(t + 2, L->bcd_dab);
    minors[0] = t[0];
    minors[1] = t[2];
    minors[2] = t[1];
    minors[3] = t[3];
}

/* the undecided record (pred_insphere_keep_) from the lanes */
static inline void pred_insphere_packed_keep_(const pred_is_lanes_ *L, double *minors,
                                              double det, double xyzmm)
{
    pred_insphere_packed_minors_(L, minors);
    minors[4] = det;
    minors[5] = xyzmm;
}

static inline int pred_insphere_packed_rest_(const pred_is_lanes_ *L, double det, double seps,
                                             double *minors)
{
    if (seps == 0) {
        if (minors) pred_insphere_packed_minors_(L, minors);
        return 0;
    }
    const __m128d mag = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
    const __m128d XY = _mm_max_pd(_mm_max_pd(_mm_and_pd(L->A, mag), _mm_and_pd(L->B, mag)),
                                  _mm_max_pd(_mm_and_pd(L->C, mag), _mm_and_pd(L->D, mag)));
    const __m128d Zs = _mm_max_pd(_mm_and_pd(L->Z1, mag), _mm_and_pd(L->Z2, mag));
    const double X = _mm_cvtsd_f64(XY), Y = _mm_cvtsd_f64(_mm_unpackhi_pd(XY, XY));
    const double Z = _mm_cvtsd_f64(_mm_max_sd(Zs, _mm_unpackhi_pd(Zs, Zs)));
    const double lo = pred_min_(pred_min_(X, Y), Z);
    const double M = pred_max_(pred_max_(X, Y), Z);
    if (!(lo >= PRED_IS_LO && M <= PRED_IS_HI)) {
        if (minors) pred_insphere_packed_keep_(L, minors, det, __builtin_inf());
        return 0;
    }
    const double eps = ((((PRED_IS_C * X) * Y) * Z) * M) * M;
    if (minors && !(det > eps) && !(det < -eps))
        pred_insphere_packed_keep_(L, minors, det, (((X * Y) * Z) * M) * M);
    return (det > eps) - (det < -eps);
}

#if defined(__AVX2__)
#include <immintrin.h>
/* pred_insphere_filter with four lanes at a time (AVX2; only translation units compiled with
 * it, kernel/insert_avx2.c): the same answer and the same record, bit for bit, by the same
 * argument as the two-lane form above (proofs/filters.md section 13).  A lane holds one
 * vertex's value, in the order (a, c, b, d) that unpacking the loaded pairs gives; rot1 gives
 * each lane the value of its vertex's successor in a -> b -> c -> d -> a, rot2 of its second
 * successor.  With v' the successor of v and v'' the second:
 *     M = X*rot1(Y) - rot1(X)*Y           v's lane: vx*v'y - v'x*vy: (ab, cd, bc, da)
 *     W = dup(X*rot2(Y) - rot2(X)*Y)       (ac, ac, bd, bd): lanes a and b, each duplicated
 *     C3 = (Z*rot1(M) - Zn*W) + rot2(Z)*M  (abc, cda, bcd, dab), Zn = rot1(Z) with the lanes
 *                                          of c and d negated: cz*da - (-dz)*ac is the scalar
 *                                          cz*da + dz*ac, as in the two-lane form
 *     lifts (x^2 + y^2) + z^2 per lane; P = lifts*rot1(C3) = (aw*bcd, cw*dab, bw*cda, dw*abc)
 *     det = (cw*dab - dw*abc) + (aw*bcd - bw*cda): the halves of P subtracted, then added.
 * Every product and difference is the scalar text's, operand for operand (a product's
 * operands swapped at most), so signed zeros agree too; the duplication (movedup) and the
 * negation (xor with -0.0) only move values or flip a sign.
 * tests/test_pred_packed_filter_avx2.c compares it with the scalar filter. */
#define PRED_INSPHERE_PACKED4 1
typedef struct pred_is_lanes4_ {
    __m256d X, Y, Z, C3;   /* the translated coordinates and the 3x3 minors, lanes a c b d */
} pred_is_lanes4_;

static inline double pred_insphere_lanes4_(const double *a, const double *b, const double *c,
                                           const double *d, const double *e, pred_is_lanes4_ *L)
{
    const __m256d P = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)),
                                           _mm_loadu_pd(b), 1);   /* ax ay bx by */
    const __m256d Q = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(c)),
                                           _mm_loadu_pd(d), 1);   /* cx cy dx dy */
    const __m256d ex = _mm256_broadcast_sd(e), ey = _mm256_broadcast_sd(e + 1);
    const __m256d ez = _mm256_broadcast_sd(e + 2);
    const __m256d X = _mm256_sub_pd(_mm256_unpacklo_pd(P, Q), ex);  /* a c b d */
    const __m256d Y = _mm256_sub_pd(_mm256_unpackhi_pd(P, Q), ey);
    const __m256d Z = _mm256_sub_pd(_mm256_set_pd(d[2], b[2], c[2], a[2]), ez);
    /* rot1: the lane of v gets v's successor's value (a->b->c->d->a): (b, d, c, a) */
#define PRED_ROT1(v) _mm256_permute4x64_pd((v), 2 | 3 << 2 | 1 << 4 | 0 << 6)
    /* rot2: v's second successor (c, a, d, b): a swap within each half */
#define PRED_ROT2(v) _mm256_permute_pd((v), 5)
    const __m256d M = _mm256_sub_pd(_mm256_mul_pd(X, PRED_ROT1(Y)), _mm256_mul_pd(PRED_ROT1(X), Y));
    /* (ac, ., bd, .) in lanes a and b, then duplicated: (ac, ac, bd, bd) */
    const __m256d W = _mm256_movedup_pd(
        _mm256_sub_pd(_mm256_mul_pd(X, PRED_ROT2(Y)), _mm256_mul_pd(PRED_ROT2(X), Y)));
    /* the successor's z with lanes c and d negated: (bz, -dz, cz, -az) */
    const __m256d Zn = _mm256_xor_pd(PRED_ROT1(Z), _mm256_set_pd(-0.0, 0.0, -0.0, 0.0));
    const __m256d C3 = _mm256_add_pd(
        _mm256_sub_pd(_mm256_mul_pd(Z, PRED_ROT1(M)), _mm256_mul_pd(Zn, W)),
        _mm256_mul_pd(PRED_ROT2(Z), M));
    const __m256d Wl = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(X, X), _mm256_mul_pd(Y, Y)),
                                     _mm256_mul_pd(Z, Z));
    const __m256d Pr = _mm256_mul_pd(Wl, PRED_ROT1(C3));   /* aw*bcd cw*dab bw*cda dw*abc */
#undef PRED_ROT1
#undef PRED_ROT2
    const __m128d D = _mm_sub_pd(_mm256_castpd256_pd128(Pr), _mm256_extractf128_pd(Pr, 1));
    L->X = X;
    L->Y = Y;
    L->Z = Z;
    L->C3 = C3;
    return _mm_cvtsd_f64(_mm_add_sd(_mm_unpackhi_pd(D, D), D));
}

/* max |v| over the four lanes (exact, order-free: section 13) */
static inline double pred_hmax4_(__m256d v)
{
    const __m256d mag = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    v = _mm256_and_pd(v, mag);
    const __m128d h = _mm_max_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    return _mm_cvtsd_f64(_mm_max_sd(h, _mm_unpackhi_pd(h, h)));
}

/* the minors abc, bcd, cda, dab from C3's lanes */
static inline void pred_insphere_packed4_minors_(const pred_is_lanes4_ *L, double *minors)
{
    double t[4];
    _mm256_storeu_pd(t, L->C3);   /* abc cda bcd dab */
    minors[0] = t[0];
    minors[1] = t[2];
    minors[2] = t[1];
    minors[3] = t[3];
}

/* pred_insphere_packed_rest_ on the four lanes' values */
static inline int pred_insphere_packed4_rest_(const pred_is_lanes4_ *L, double det, double seps,
                                              double *minors)
{
    if (seps == 0) {
        if (minors) pred_insphere_packed4_minors_(L, minors);
        return 0;
    }
    const double X = pred_hmax4_(L->X), Y = pred_hmax4_(L->Y), Z = pred_hmax4_(L->Z);
    const double lo = pred_min_(pred_min_(X, Y), Z);
    const double M = pred_max_(pred_max_(X, Y), Z);
    if (!(lo >= PRED_IS_LO && M <= PRED_IS_HI)) {
        if (minors) {
            pred_insphere_packed4_minors_(L, minors);
            minors[4] = det;
            minors[5] = __builtin_inf();
        }
        return 0;
    }
    const double eps = ((((PRED_IS_C * X) * Y) * Z) * M) * M;
    if (minors && !(det > eps) && !(det < -eps)) {
        pred_insphere_packed4_minors_(L, minors);
        minors[4] = det;
        minors[5] = (((X * Y) * Z) * M) * M;
    }
    return (det > eps) - (det < -eps);
}
#endif

#if defined(__AVX2__)
/* The visibility walk's four orient3d filters at once (AVX2; kernel/walk.h): lane f is
 * pred_orient3d_filter(q[0], q[1], q[2], q[3], seps) with q = (v0, v1, v2, v3) and q[f]
 * replaced by p, the sign of the tet with its vertex f moved to p.  Each lane's tuple is made
 * by blends of broadcast coordinates (moves), and every difference, product and sum is the
 * scalar text's, on the same operands, in the same order (a product's operands swapped at
 * most), so det~ is the scalar det~ bit for bit (proofs/filters.md section 13).  The static
 * test, then, for the lanes it leaves and seps != 0, the semi-static one: the maxima are exact
 * and order-free since no translation of finite points is NaN (section 13), the guard is the
 * scalar guard, eps the scalar product chain.  Bit f of *neg: lane f decided negative; of
 * *und: undecided (the scalar filter returns 0, and pred_orient3d_rest decides).
 * Inlined always: as a call the walk lost a third of what the lanes save (NOTES.md E173).
 * tests/test_pred_packed_filter_avx2.c compares every lane with the scalar filter. */
#define PRED_ORIENT3D_FACETS4 1
__attribute__((always_inline)) static inline void pred_orient3d_facets4_(
    const double *v0, const double *v1, const double *v2, const double *v3, const double *p,
    double seps, unsigned *neg, unsigned *und)
{
    __m256d A[3], B[3], C[3], D[3];   /* lane f: the tuple's a, b, c, d, coordinate by coordinate */
    for (int j = 0; j < 3; j++) {
        const __m256d pj = _mm256_broadcast_sd(p + j);
        A[j] = _mm256_blend_pd(_mm256_broadcast_sd(v0 + j), pj, 1);
        B[j] = _mm256_blend_pd(_mm256_broadcast_sd(v1 + j), pj, 2);
        C[j] = _mm256_blend_pd(_mm256_broadcast_sd(v2 + j), pj, 4);
        D[j] = _mm256_blend_pd(_mm256_broadcast_sd(v3 + j), pj, 8);
    }
    const __m256d px = _mm256_sub_pd(B[0], A[0]), py = _mm256_sub_pd(B[1], A[1]);
    const __m256d pz = _mm256_sub_pd(B[2], A[2]);
    const __m256d qx = _mm256_sub_pd(C[0], A[0]), qy = _mm256_sub_pd(C[1], A[1]);
    const __m256d qz = _mm256_sub_pd(C[2], A[2]);
    const __m256d rx = _mm256_sub_pd(D[0], A[0]), ry = _mm256_sub_pd(D[1], A[1]);
    const __m256d rz = _mm256_sub_pd(D[2], A[2]);
    const __m256d m1 = _mm256_sub_pd(_mm256_mul_pd(qy, rz), _mm256_mul_pd(qz, ry));
    const __m256d m2 = _mm256_sub_pd(_mm256_mul_pd(qz, rx), _mm256_mul_pd(qx, rz));
    const __m256d m3 = _mm256_sub_pd(_mm256_mul_pd(qx, ry), _mm256_mul_pd(qy, rx));
    const __m256d det = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(px, m1), _mm256_mul_pd(py, m2)), _mm256_mul_pd(pz, m3));
    const __m256d s = _mm256_set1_pd(seps), ms = _mm256_set1_pd(-seps);
    const unsigned pos = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(det, s, _CMP_GT_OQ));
    const unsigned n = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(det, ms, _CMP_LT_OQ));
    const unsigned left = 15u & ~(pos | n);
    if (__builtin_expect(left == 0, 1) || seps == 0) {
        *neg = n;
        *und = left;
        return;
    }
    const __m256d mag = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
#define PRED_ABS4(v) _mm256_and_pd((v), mag)
    const __m256d X = _mm256_max_pd(_mm256_max_pd(PRED_ABS4(px), PRED_ABS4(qx)), PRED_ABS4(rx));
    const __m256d Y = _mm256_max_pd(_mm256_max_pd(PRED_ABS4(py), PRED_ABS4(qy)), PRED_ABS4(ry));
    const __m256d Z = _mm256_max_pd(_mm256_max_pd(PRED_ABS4(pz), PRED_ABS4(qz)), PRED_ABS4(rz));
#undef PRED_ABS4
    const __m256d lo = _mm256_min_pd(_mm256_min_pd(X, Y), Z);
    const __m256d hi = _mm256_max_pd(_mm256_max_pd(X, Y), Z);
    const __m256d guard = _mm256_and_pd(_mm256_cmp_pd(lo, _mm256_set1_pd(PRED_O3_LO), _CMP_GE_OQ),
                                        _mm256_cmp_pd(hi, _mm256_set1_pd(PRED_O3_HI), _CMP_LE_OQ));
    const __m256d CX = _mm256_mul_pd(_mm256_set1_pd(PRED_O3_C), X);
    const __m256d eps = _mm256_mul_pd(_mm256_mul_pd(CX, Y), Z);   /* ((C * X) * Y) * Z */
    const __m256d meps = _mm256_xor_pd(eps, _mm256_set1_pd(-0.0));
    const unsigned g = (unsigned)_mm256_movemask_pd(guard);
    const unsigned pos2 = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(det, eps, _CMP_GT_OQ)) & g;
    const unsigned n2 = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(det, meps, _CMP_LT_OQ)) & g;
    *neg = n | (left & n2);
    *und = left & ~(pos2 | n2);
}
#endif

/* det~ and the static test on the lanes (four where AVX2 is compiled in, else two), then the
 * rest of the scalar filter on their values; *static_misses counts the calls the static test
 * leaves to the rest (the kernel's choice of filter order, kernel/conflict.h). */
static inline int pred_insphere_filter_packed(const double *a, const double *b, const double *c,
                                              const double *d, const double *e, double seps,
                                              double *minors, uint64_t *static_misses)
{
#if defined(__AVX2__)
    pred_is_lanes4_ L;
    const double det = pred_insphere_lanes4_(a, b, c, d, e, &L);
    if (det > seps) return 1;
    if (det < -seps) return -1;
    ++*static_misses;
    return pred_insphere_packed4_rest_(&L, det, seps, minors);
#else
    pred_is_lanes_ L;
    const double det = pred_insphere_lanes_(a, b, c, d, e, &L);
    if (det > seps) return 1;
    if (det < -seps) return -1;
    ++*static_misses;
    return pred_insphere_packed_rest_(&L, det, seps, minors);
#endif
}

/* The smallest power of two above m (finite, m >= 0), or +inf past the largest. */
static inline double pred_pow2_above_(double m)
{
    uint64_t u;
    __builtin_memcpy(&u, &m, sizeof u);
    u = (u & UINT64_C(0x7ff0000000000000)) + (UINT64_C(1) << 52);
    double w;
    __builtin_memcpy(&w, &u, sizeof w);
    return w;
}

/* pred_insphere_filter_packed with a static test on the thread's level first: when every
 * computed translated coordinate of the tuple lies below lv->w in magnitude, the static bound
 * of a box of extents w, w, w (lv->sw) holds for it (proofs/filters.md section 8, X' = Y' = Z'
 * = w; lv->sw is the smaller of that bound and seps), and it decides wherever the mesh is
 * finer than the global box's bound (seps) sees.
 * The same answer as pred_insphere_filter: a tuple inside w has maxima X, Y, Z <= w, so its
 * semi-static eps <= sw (the same product chain, rounding monotone) and |det~| > sw decides
 * the scalar filter too, with the sign of det~.  A call the level leaves is the static-first
 * filter's; it counts a miss and moves the level to the power of two above its largest
 * coordinate, so the next tuples of the cavity are judged at their own scale. */
#if defined(__AVX2__)
/* The level filter's two steps, shared with the kernel's form of it (kernel/conflict.h
 * km_conflict_bit): the lanes' |coordinate| maxima and the bound they select (the level's
 * when all lie below lv->w, else seps); after a miss, the level moved to the power of two
 * above their largest. */
static inline __m256d pred_insphere_lane_max_(const pred_is_lanes4_ *L)
{
    const __m256d mag = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    return _mm256_max_pd(_mm256_max_pd(_mm256_and_pd(L->X, mag), _mm256_and_pd(L->Y, mag)),
                         _mm256_and_pd(L->Z, mag));
}

static inline double pred_insphere_level_bound_(const pred_is_lanes4_ *L, const pred_is_level *lv,
                                                double seps, __m256d *m)
{
    *m = pred_insphere_lane_max_(L);
    const int inside =
        _mm256_movemask_pd(_mm256_cmp_pd(*m, _mm256_set1_pd(lv->w), _CMP_LT_OQ)) == 0xF;
    return inside ? lv->sw : seps;
}

static inline void pred_insphere_level_move_(pred_is_level *lv, __m256d m, double seps)
{
    const double M = pred_hmax4_(m);
    if (M == M && M < PRED_IS_HI) {
        lv->w = pred_pow2_above_(M);
        lv->sw = pred_min_(pred_insphere_static_eps(lv->w, lv->w, lv->w), seps);
    }
}

static inline int pred_insphere_filter_packed_lv(const double *a, const double *b,
                                                 const double *c, const double *d,
                                                 const double *e, double seps,
                                                 pred_is_level *lv, double *minors,
                                                 uint64_t *static_misses)
{
    pred_is_lanes4_ L;
    const double det = pred_insphere_lanes4_(a, b, c, d, e, &L);
    __m256d m;
    const double t = pred_insphere_level_bound_(&L, lv, seps, &m);
    if (det > t) return 1;
    if (det < -t) return -1;
    ++*static_misses;
    pred_insphere_level_move_(lv, m, seps);
    return pred_insphere_packed4_rest_(&L, det, seps, minors);
}
#endif

/* the semi-static-first decision from det~ and the maxima X, Y, Z (below) */
static inline int pred_insphere_sf_decide_(double det, double X, double Y, double Z, double seps)
{
    const double lo = pred_min_(pred_min_(X, Y), Z);
    const double M = pred_max_(pred_max_(X, Y), Z);
    const double eps = ((((PRED_IS_C * X) * Y) * Z) * M) * M;
    const int guard = (lo >= PRED_IS_LO) & (M <= PRED_IS_HI);
    const double bound = guard ? pred_min_(eps, seps) : seps;
    return (det > bound) - (det < -bound);
}

/* The same filter with the semi-static bound first: the same answer and the same record as
 * pred_insphere_filter, bit for bit, for inputs where the static bound seldom decides (surface
 * samples, spheres: the static test's branch goes either way at random there, and every call
 * it misses pays the rest anyway).  Why the answers agree: pred_insphere_filter decides, with
 * the sign of det~, exactly when |det~| > seps or (the guard holds and |det~| > eps), where
 * eps = ((((C*X)*Y)*Z)*M)*M.  Here the bound is min(eps, seps) when the guard holds, seps when
 * it does not, and |det~| > min(eps, seps) is |det~| > eps or |det~| > seps (both are valid
 * bounds when the guard holds: proofs/filters.md (S) and section 8).  The guard's NaN rule is the
 * scalar text's (a NaN translation fails it), a NaN det~ decides nothing, seps = 0 (a lattice)
 * gives a bound 0 (eps >= 0 when the guard holds) and PRED_NO_STATIC (+inf) gives eps.  An
 * undecided call runs pred_insphere_packed_rest_, which leaves the record.  The bound is chosen
 * without a branch: one branch a call, on whether anything was decided (taken rarely).
 * tests/test_pred_packed_filter.c compares answers and records with the scalar filter's. */
static inline int pred_insphere_filter_packed_sf(const double *a, const double *b,
                                                 const double *c, const double *d,
                                                 const double *e, double seps, double *minors)
{
#if defined(__AVX2__)
    pred_is_lanes4_ L;
    const double det = pred_insphere_lanes4_(a, b, c, d, e, &L);
    const int s = pred_insphere_sf_decide_(det, pred_hmax4_(L.X), pred_hmax4_(L.Y),
                                           pred_hmax4_(L.Z), seps);
    if (__builtin_expect(s == 0, 0)) return pred_insphere_packed4_rest_(&L, det, seps, minors);
    return s;
#else
    pred_is_lanes_ L;
    const double det = pred_insphere_lanes_(a, b, c, d, e, &L);
    const __m128d mag = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
    const __m128d XY = _mm_max_pd(_mm_max_pd(_mm_and_pd(L.A, mag), _mm_and_pd(L.B, mag)),
                                  _mm_max_pd(_mm_and_pd(L.C, mag), _mm_and_pd(L.D, mag)));
    const __m128d Zs = _mm_max_pd(_mm_and_pd(L.Z1, mag), _mm_and_pd(L.Z2, mag));
    const int s = pred_insphere_sf_decide_(
        det, _mm_cvtsd_f64(XY), _mm_cvtsd_f64(_mm_unpackhi_pd(XY, XY)),
        _mm_cvtsd_f64(_mm_max_sd(Zs, _mm_unpackhi_pd(Zs, Zs))), seps);
    if (__builtin_expect(s == 0, 0)) return pred_insphere_packed_rest_(&L, det, seps, minors);
    return s;
#endif
}

static inline int pred_insphere_filter_packed_lv_or_(const double *a, const double *b,
                                                     const double *c, const double *d,
                                                     const double *e, double seps,
                                                     pred_is_level *lv, double *minors,
                                                     uint64_t *static_misses)
{
#if defined(__AVX2__)
    return pred_insphere_filter_packed_lv(a, b, c, d, e, seps, lv, minors, static_misses);
#else
    (void)lv;
    const int s = pred_insphere_filter_packed_sf(a, b, c, d, e, seps, minors);
    *static_misses += s == 0;
    return s;
#endif
}
#endif


#endif
