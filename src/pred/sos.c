/* sos.c -- symbolic perturbation: insphere_sos, the hull (ghost) rule and the perturbed
 * coplanar in-circle test, exactly as CGAL's Delaunay_triangulation_3 decides them
 * (side_of_oriented_sphere / coplanar_side_of_bounded_circle with perturb = true, and
 * side_of_sphere for a cell whose vertex 3 is infinite), so that gigatet's output equals CGAL's.
 *
 * Perturbation order: the lexicographic (x, y, z) rank of the points (pred_lex_cmp), as
 * CGAL's Perturbation_order (compare_xyz).  Devillers & Teillaud (CGTA 2011) perturb the lifted
 * coordinate of each point by eps^(rank); expanding the perturbed determinant, the coefficient
 * of the highest-ranked point's term is the orientation of the other four (with the query in
 * its place), so:
 *   insphere_sos: exact sign if non-zero; else for the largest, then the second largest of the
 *     5 points: if it is e -> -orient3d(a,b,c,d) (= -1 for CGAL's positively oriented cells,
 *     the sign flips with the orientation as for the unperturbed predicate); otherwise orient3d of (a,b,c,d) with that point replaced by e,
 *     if non-zero.  (Two steps suffice when orient3d(a,b,c,d) != 0, D&T Lemma; if they do not,
 *     the precondition was violated and we return -1, CGAL's fallback.)
 *   coplanar circle: the same in the plane with CGAL's coplanar_orientation (first non-zero of
 *     the xy, yz, xz projections), three steps, the answer multiplied by `local` =
 *     coplanar_orientation(a,b,c), and -local when all three vanish.
 *
 * Exact coplanar in-circle (our own formula).  For coplanar a,b,c,e with a,b,c not collinear,
 * pick the first coordinate plane (u,w) in the order xy, yz, xz where o2 = orient2d_uw(a,b,c)
 * != 0 (the projection is then an affine bijection of the common plane P onto R^2).  Let
 * d_p = (p-e)_{uw} and Q(d_p) = |p-e|^2 (3D).  On P, Q is a positive definite quadratic form of
 * the projected difference, and the circle through a,b,c is {p : f(p) = 0} with f(p) =
 * |p-o|^2 - r^2 = Q(d_p) + (linear in d_p) + f(e).  Then
 *     D = det[d_a Q_a; d_b Q_b; d_c Q_c] = det[d_a Q_a 1; d_b Q_b 1; d_c Q_c 1; 0 0 1]
 * and adding the linear and constant parts to the Q column (column operations) replaces Q_p by
 * f(p), which is 0 for a,b,c and f(e) for the last row: D = -f(e) * orient2d_uw(a,b,c).  So e
 * is strictly inside the circle (f(e) < 0) iff sign(D) * o2 > 0:
 *     incircle = sign(D) * o2   (+1 inside, -1 outside, 0 on the circle).
 * This equals CGAL's coplanar_side_of_bounded_circleC3 (the sphere through a,b,c and e + n,
 * n = (b-a) x (c-a), cut by P is the circle), and both are 0 when a,b,c are collinear.
 *
 * Every decision of the perturbation goes through decided(): it is counted (sos_calls once per
 * call, sos_depth[term-1] for the term that decided) and, when the caller passes a log
 * (pred_sos_log, the kernel's per-thread record of gtet_options.degeneracies), appended to it,
 * so a log and the counters of the same calls always agree.
 */
#include "pred_internal.h"

#include <stdlib.h>

/* cold and out of line: the perturbation's code stays as compact as without a log */
__attribute__((cold, noinline)) void pred_sos_log_add(pred_sos_log *log, int kind,
                                                      const double *const *p, int np, int term,
                                                      int sign)
{
    log->total++;
    if (log->n >= log->limit) return;
    if (log->n == log->cap) {
        size_t cap = log->cap ? log->cap * 2 : 256;
        if (cap > log->limit) cap = log->limit;
        gtet_degeneracy *r = realloc(log->rec, cap * sizeof *r);
        if (!r) {
            log->failed |= PRED_SOS_LOG_NOMEM;
            return;
        }
        log->rec = r;
        log->cap = cap;
    }
    gtet_degeneracy *r = &log->rec[log->n++];
    r->kind = kind;
    r->npoints = np;
    for (int i = 0; i < 5; i++) {
        uint32_t id = UINT32_MAX;
        if (i < np) {
            /* compare addresses as integers: p[i] need not point into base */
            const uintptr_t b = (uintptr_t)log->base, q = (uintptr_t)p[i];
            const uintptr_t off = q - b, size = 3 * sizeof(double);
            if (q >= b && off % size == 0 && off / size < log->nv) id = (uint32_t)(off / size);
            else log->failed |= PRED_SOS_LOG_FOREIGN;
        }
        r->vertex[i] = id;
    }
    r->term = term;
    r->sign = sign;
}

/* Count a decision of the perturbation made by term `term` (1-based), record it when there is
 * a log, and return its sign. */
static inline int decided(pred_counters *cnt, pred_sos_log *log, int kind,
                          const double *const *p, int np, int term, int sign)
{
    cnt->sos_depth[term - 1]++;
    if (__builtin_expect(log != NULL, 0)) pred_sos_log_add(log, kind, p, np, term, sign);
    return sign;
}

/* idx[0..n-1] = 0..n-1 sorted by increasing lexicographic rank of p[idx[i]] */
static void lex_sort(const double *const *p, int n, int *idx)
{
    for (int i = 0; i < n; i++) idx[i] = i;
    for (int i = 1; i < n; i++) {
        int k = idx[i], j = i;
        while (j > 0 && pred_lex_cmp(p[idx[j - 1]], p[k]) > 0) {
            idx[j] = idx[j - 1];
            j--;
        }
        idx[j] = k;
    }
}

int pred_orient2d_exact(const double *a, const double *b, const double *c, int u, int w)
{
    int s;
    if (pred_orient2d_int(a, b, c, u, w, &s) || pred_orient2d_wide(a, b, c, u, w, &s)) return s;
    return pred_orient2d_gmp(a, b, c, u, w);
}

int pred_lifted2d_exact(const double *a, const double *b, const double *c, const double *e,
                        int u, int w)
{
    int d;
    if (pred_lifted2d_int(a, b, c, e, u, w, &d) || pred_lifted2d_wide(a, b, c, e, u, w, &d))
        return d;
    return pred_lifted2d_gmp(a, b, c, e, u, w);
}

/* CGAL's 3-argument coplanar_orientation: first non-zero projection among xy, yz, xz. */
static int coplanar_orientation(const double *a, const double *b, const double *c)
{
    int o = pred_orient2d_exact(a, b, c, 0, 1);
    if (o != 0) return o;
    o = pred_orient2d_exact(a, b, c, 1, 2);
    if (o != 0) return o;
    return pred_orient2d_exact(a, b, c, 0, 2);
}

int pred_coplanar_orientation(const double *a, const double *b, const double *c,
                              pred_counters *cnt)
{
    (void)cnt;  /* 2D orientations are not counted (see pred.h) */
    return coplanar_orientation(a, b, c);
}

/* Exact unperturbed coplanar in-circle (see the file comment). */
static int incircle_coplanar_exact(const double *a, const double *b, const double *c,
                                   const double *e)
{
    static const int axes[3][2] = {{0, 1}, {1, 2}, {0, 2}};
    for (int k = 0; k < 3; k++) {
        int u = axes[k][0], w = axes[k][1];
        int o2 = pred_orient2d_exact(a, b, c, u, w);
        if (o2 == 0) continue;
        return pred_lifted2d_exact(a, b, c, e, u, w) * o2;
    }
    return 0; /* a, b, c collinear */
}

static int incircle_coplanar_sos(const double *a, const double *b, const double *c,
                                 const double *e, pred_counters *cnt, pred_sos_log *log)
{
    int s = incircle_coplanar_exact(a, b, c, e);
    if (s != 0) return s;
    cnt->sos_calls++;
    const double *p[4] = {a, b, c, e};
    int idx[4];
    lex_sort(p, 4, idx);
    const int local = coplanar_orientation(a, b, c);
    for (int i = 3; i > 0; i--) {
        const int k = idx[i];
        if (k == 3) /* e itself: outside (a,b,c are not collinear) */
            return decided(cnt, log, GTET_DEGENERACY_COPLANAR, p, 4, 4 - i, -1);
        const double *q[3] = {a, b, c};
        q[k] = e; /* the leading monomial's coefficient: a,b,c with p[k] replaced by e */
        const int o = coplanar_orientation(q[0], q[1], q[2]);
        if (o != 0) return decided(cnt, log, GTET_DEGENERACY_COPLANAR, p, 4, 4 - i, o * local);
    }
    return decided(cnt, log, GTET_DEGENERACY_COPLANAR, p, 4, 4, -local);
}

int pred_incircle_coplanar_sos(const double *a, const double *b, const double *c,
                               const double *e, pred_counters *cnt)
{
    return incircle_coplanar_sos(a, b, c, e, cnt, NULL);
}

/* i1 = index of the lexicographically largest of p[0..4], i2 = of the second largest (the
 * only two ranks the perturbation ever needs: two steps suffice, see the top of this file). */
static void lex_top2(const double *const *p, int *i1, int *i2)
{
    const int first = pred_lex_cmp(p[0], p[1]) < 0;
    int a = first, b = 1 - first;
    for (int i = 2; i < 5; i++) {  /* selects, not branches (ties mispredict on lattices) */
        const int over_a = pred_lex_cmp(p[i], p[a]) > 0;
        const int over_b = pred_lex_cmp(p[i], p[b]) > 0;
        b = over_a ? a : over_b ? i : b;
        a = over_a ? i : a;
    }
    *i1 = a;
    *i2 = b;
}

/* The same two ranks on a lattice (ps->is_exact: coordinates multiples of 2^s, every extent
 * at most 659 units): the lexicographic order of p is the order of the exact number
 * key(p) - key(e) = (p-e)_x 2^22 + (p-e)_y 2^11 + (p-e)_z, because every coordinate difference
 * of the set is at most 659 < 2^10 units, so the y and z terms (< 2^21 + 2^10 units) never
 * outweigh one unit of the x term, nor the z term one unit of the y term; every operation is
 * exact (multiples of 2^s below 2^33 units; proofs/filters.md section 9).  e's own key is 0.
 * One double compare per pair instead of three coordinate compares. */
static void lex_top2_lattice(const double *const *p, int *i1, int *i2)
{
    const double *e = p[4];
    double k[5];
    for (int i = 0; i < 4; i++)
        k[i] = ((p[i][0] - e[0]) * 0x1p22 + (p[i][1] - e[1]) * 0x1p11) + (p[i][2] - e[2]);
    k[4] = 0.0;
    const int first = k[0] < k[1];
    int a = first, b = 1 - first;
    for (int i = 2; i < 5; i++) {
        const int over_a = k[i] > k[a];
        const int over_b = k[i] > k[b];
        b = over_a ? a : over_b ? i : b;
        a = over_a ? i : a;
    }
    *i1 = a;
    *i2 = b;
}

/* The same two ranks on a set of integers below 2^23 in magnitude (pred_static.int23): the
 * lexicographic order of p is that of the pairs (k(p), z(p)), k(p) = x(p) 2^24 + y(p) as an
 * exact int64 (|k| < 2^47 + 2^23): if x(p) > x(q) then k(p) - k(q) >= 2^24 - |y(p) - y(q)| >
 * 0, as |y(p) - y(q)| < 2^24; else k's order is y's.  -0.0 converts to 0 and compares equal
 * to +0.0, as in pred_lex_cmp.  Two integer compares and one double compare a pair instead of
 * three coordinate compares (NOTES.md E91). */
static void lex_top2_int23(const double *const *p, int *i1, int *i2)
{
    int64_t k[5];
    double z[5];
    for (int i = 0; i < 5; i++) {
        k[i] = (int64_t)p[i][0] * ((int64_t)1 << 24) + (int64_t)p[i][1];
        z[i] = p[i][2];
    }
#define LEX_OVER(i, j) (k[i] > k[j] || (k[i] == k[j] && z[i] > z[j]))
    const int first = !LEX_OVER(0, 1);
    int a = first, b = 1 - first;
    for (int i = 2; i < 5; i++) {
        const int over_a = LEX_OVER(i, a);
        const int over_b = LEX_OVER(i, b);
        b = over_a ? a : over_b ? i : b;
        a = over_a ? i : a;
    }
#undef LEX_OVER
    *i1 = a;
    *i2 = b;
}

/* orient3d of (a,b,c,d) with point k replaced by e, from the exact minors of the translated
 * points A = a-e, ..., D = d-e (abc = det[A;B;C], bcd = det[B;C;D], cda = det[C;D;A],
 * dab = det[D;A;B]): orient3d(e,b,c,d) = bcd, orient3d(a,e,c,d) = -cda, orient3d(a,b,e,d) =
 * dab, orient3d(a,b,c,e) = -abc; and orient3d(a,b,c,d) = bcd - cda + dab - abc (expansion of
 * the 4x4 determinant with a column of ones).  Tested against pred_orient3d
 * (tests/test_pred_perturbation.c). */
static int orient_from_minors(const double *mn, int k)
{
    double v;
    switch (k) {
    case 0: v = mn[1]; break;
    case 1: v = -mn[2]; break;
    case 2: v = mn[3]; break;
    case 3: v = -mn[0]; break;
    default: v = ((mn[1] - mn[2]) + mn[3]) - mn[0]; break;  /* exact: each <= 6 E^3 units
                                                              (6XYZ, filters.md 12) */
    }
    return (v > 0) - (v < 0);
}

/* orient_from_minors on the exact integer minors of pred_insphere_int_m (|minor| < 2^75, so
 * the sum of four cannot overflow), counted as an orient3d call as the lattice path counts
 * its reads of the minors. */
static int orient_from_int_minors(const pred_i128 *mn, int k, pred_counters *cnt)
{
    pred_i128 v;
    switch (k) {
    case 0: v = mn[1]; break;
    case 1: v = -mn[2]; break;
    case 2: v = mn[3]; break;
    case 3: v = -mn[0]; break;
    default: v = ((mn[1] - mn[2]) + mn[3]) - mn[0]; break;
    }
    cnt->orient_calls++;
    if (v == 0 && k < 4) cnt->orient_zero++;
    return (v > 0) - (v < 0);
}

/* The perturbation of an exactly zero insphere (the file comment), its orient3d evaluated for
 * points of ps's set, or read off the exact minors mn (pred_insphere_filter's, exact on a
 * lattice or by proofs/filters.md section 12) or the exact integer minors im
 * (pred_insphere_int_m) when not NULL; lattice: ps->is_exact (the ranks by lex_top2_lattice). */
static int insphere_perturbed(const double *a, const double *b, const double *c, const double *d,
                              const double *e, const pred_static *ps, const double *mn,
                              const pred_i128 *im, pred_counters *cnt, pred_sos_log *log)
{
    cnt->sos_calls++;
    const double *p[5] = {a, b, c, d, e};
    int top[2];
    if (mn && ps->is_exact)
        lex_top2_lattice(p, &top[0], &top[1]);
    else if (ps->int23)
        lex_top2_int23(p, &top[0], &top[1]);
    else
        lex_top2(p, &top[0], &top[1]);
    for (int i = 0; i < 2; i++) {
        const int k = top[i];
        if (k == 4) {
            /* e's own term: its coefficient is -orient3d(a,b,c,d), i.e. -1 (outside) under
             * CGAL's precondition orient3d > 0; the general form keeps the result
             * antisymmetric in (a,b,c,d) when the tet is negatively oriented. */
            int o;
            if (im) {
                o = orient_from_int_minors(im, 4, cnt);
            } else if (mn) {
                cnt->orient_calls++;
                o = orient_from_minors(mn, 4);
            } else {
                o = pred_orient3d_st(a, b, c, d, ps, cnt);
            }
            return decided(cnt, log, GTET_DEGENERACY_COSPHERICAL, p, 5, i + 1, o != 0 ? -o : -1);
        }
        int o;
        if (im) {
            o = orient_from_int_minors(im, k, cnt);
        } else if (mn) {
            cnt->orient_calls++;
            o = orient_from_minors(mn, k);
            if (o == 0) cnt->orient_zero++;
        } else {
            const double *q[4] = {a, b, c, d};
            q[k] = e;
            o = pred_orient3d_st(q[0], q[1], q[2], q[3], ps, cnt);
        }
        if (o != 0) return decided(cnt, log, GTET_DEGENERACY_COSPHERICAL, p, 5, i + 1, o);
    }
    /* only when orient3d(a,b,c,d) == 0 (precondition violated) */
    return decided(cnt, log, GTET_DEGENERACY_COSPHERICAL, p, 5, 3, -1);
}

int pred_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                      const double *e, pred_counters *cnt)
{
    const int s = pred_insphere(a, b, c, d, e, cnt);
    if (s != 0) return s;
    return insphere_perturbed(a, b, c, d, e, &pred_static_none, NULL, NULL, cnt, NULL);
}

int pred_insphere_sos_rest_log(const double *a, const double *b, const double *c,
                               const double *d, const double *e, const pred_static *ps,
                               const double *minors, pred_counters *cnt, pred_sos_log *log)
{
    cnt->insphere_calls++;
    if (ps->is_exact) {  /* det~ == 0 is the exact determinant */
        cnt->insphere_zero++;
        return insphere_perturbed(a, b, c, d, e, ps, minors, NULL, cnt, log);
    }
    /* a set of small integers (grids, the paraboloid): the integer stage decides, without its
     * range checks (any other set tries it first in pred_insphere_exact), and on a zero hands
     * over its exact minors, off which the perturbation reads its orient3d signs (NOTES.md
     * E30); counted as pred_insphere_exact counts it */
    pred_i128 im[4];
    int s;
    if (ps->int23 && minors && minors[5] <= PRED_IS_INT_EXACT) {
        /* the filter's evaluation was exact (proofs/filters.md section 12): its det~ is the
         * determinant and its minors are exact; counted as the integer stage counts it */
        cnt->insphere_exact++;
        cnt->insphere_int++;
        s = (minors[4] > 0) - (minors[4] < 0);
        if (s != 0) return s;
        cnt->insphere_zero++;
        return insphere_perturbed(a, b, c, d, e, ps, minors, NULL, cnt, log);
    }
    if (ps->int23 && pred_insphere_int_m(a, b, c, d, e, 1, &s, im)) {  /* always applies */
        cnt->insphere_exact++;
        cnt->insphere_int++;
        if (s != 0) return s;
        cnt->insphere_zero++;
        return insphere_perturbed(a, b, c, d, e, ps, NULL, im, cnt, log);
    }
    s = pred_insphere_exact(a, b, c, d, e, cnt);
    if (s != 0) return s;
    return insphere_perturbed(a, b, c, d, e, ps, NULL, NULL, cnt, log);
}

int pred_insphere_sos_rest(const double *a, const double *b, const double *c, const double *d,
                           const double *e, const pred_static *ps, const double *minors,
                           pred_counters *cnt)
{
    return pred_insphere_sos_rest_log(a, b, c, d, e, ps, minors, cnt, NULL);
}

int pred_ghost_conflict_log(const double *a, const double *b, const double *c,
                            const double *e, pred_counters *cnt, pred_sos_log *log)
{
    const int o = pred_orient3d(a, b, c, e, cnt);
    if (o != 0) return o;
    return incircle_coplanar_sos(a, b, c, e, cnt, log);
}

int pred_ghost_conflict_st_log(const double *a, const double *b, const double *c,
                               const double *e, const pred_static *ps, pred_counters *cnt,
                               pred_sos_log *log)
{
    const int o = pred_orient3d_st(a, b, c, e, ps, cnt);
    if (o != 0) return o;
    return incircle_coplanar_sos(a, b, c, e, cnt, log);
}

int pred_ghost_conflict(const double *a, const double *b, const double *c, const double *e,
                        pred_counters *cnt)
{
    return pred_ghost_conflict_log(a, b, c, e, cnt, NULL);
}
