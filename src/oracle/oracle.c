/* oracle.c -- the independent exact oracle: signs of orient3d / insphere / the hull rule and
 * their symbolic perturbation, in plain GMP integer arithmetic.
 *
 * Exactness.  Every finite double is x = m * 2^e with an integer m (|m| < 2^53, made odd) and
 * -1074 <= e <= 971.  For the k points of one predicate call we take E = the smallest e over
 * their nonzero coordinates and represent each coordinate by the integer x * 2^-E = m * 2^(e-E)
 * (an mpz, exact).  Every polynomial evaluated below is homogeneous in the coordinates (of
 * degree 2, 3, 4 or 5), so multiplying all coordinates by the positive number 2^-E multiplies
 * it by a positive number and keeps its sign.  All arithmetic after that is mpz (exact), so each
 * sign is the true sign of the polynomial on the doubles as given.  This is the "exact rational
 * value of each double" of mpq_set_d, without mpq's gcd on every operation.
 *
 * Conventions (those of gigatet.h):
 *   orient3d(a,b,c,d) = sign det[b-a; c-a; d-a]            (+1 for (0, e_x, e_y, e_z))
 *   insphere(a,b,c,d,e) = +1 when e is strictly inside the sphere through a,b,c,d and
 *       orient3d(a,b,c,d) > 0; the sign flips with the orientation.  It is computed as
 *       -sign det[x-e, |x-e|^2] (rows x = a,b,c,d): for the positive simplex
 *       (0, e_x, e_y, e_z) and e = 0.25*(1,1,1), inside, that determinant is negative
 *       (tests/test_oracle_predicates.c checks this and the sign flips).
 *
 * Points whose scaled coordinates are below 2^22 take an equivalent 128-bit integer path
 * (oracle_small.c); the rest is mpz.
 *
 * Symbolic perturbation: transcribed from the specification in CGAL's
 * Delaunay_triangulation_3.h (side_of_oriented_sphere, coplanar_side_of_bounded_circle and
 * side_of_sphere with an infinite vertex) and kernel_ftC3.h (coplanar_orientationC3,
 * coplanar_side_of_bounded_circleC3); see the comment above each function.  Points are ranked
 * by lexicographic (x, y, z) order of their values (-0.0 == +0.0).  Nothing here is shared with
 * src/pred/.  Simple code first; the few fast paths (small integers, fixed-width sums) argue
 * their exactness where they stand.  No global state, reentrant.
 */
#include "oracle.h"
#include "oracle_small.h"

#include <gmp.h>
#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>

typedef struct zpt { mpz_t c[3]; } zpt;

/* x = m * 2^e with m odd, |m| < 2^53; for x == 0: m = 0. */
void orc_split_double(double x, double *m, int *e)
{
    if (x == 0.0) {
        *m = 0.0;
        *e = INT_MAX;
        return;
    }
    int ex;
    double f = frexp(x, &ex);                 /* x = f * 2^ex, 0.5 <= |f| < 1, exact */
    int64_t mi = (int64_t)ldexp(f, 53);       /* exact: a double has at most 53 significant bits */
    ex -= 53;
    /* strip trailing zero bits: small integers stay small (mi != 0, |mi| < 2^53) */
    uint64_t mag = mi < 0 ? (uint64_t)(-mi) : (uint64_t)mi;
    int tz = __builtin_ctzll(mag);
    mag >>= tz;
    mi = mi < 0 ? -(int64_t)mag : (int64_t)mag;
    ex += tz;
    *m = (double)mi;                          /* |mi| < 2^53: exact */
    *e = ex;
}

#define ORC_MAX_LOAD 16

/* Load k points (k <= ORC_MAX_LOAD) as integers with one common power-of-two scale (see the
 * top). */
static void load(zpt *z, const double *const *p, int k)
{
    double m[ORC_MAX_LOAD][3];
    int e[ORC_MAX_LOAD][3];
    int emin = INT_MAX;
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++) {
            orc_split_double(p[i][j], &m[i][j], &e[i][j]);
            if (m[i][j] != 0.0 && e[i][j] < emin) emin = e[i][j];
        }
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++) {
            mpz_init(z[i].c[j]);
            if (m[i][j] != 0.0) {
                mpz_set_d(z[i].c[j], m[i][j]);
                mpz_mul_2exp(z[i].c[j], z[i].c[j], (mp_bitcnt_t)(e[i][j] - emin));
            }
        }
}

static void unload(zpt *z, int k)
{
    for (int i = 0; i < k; i++)
        for (int j = 0; j < 3; j++) mpz_clear(z[i].c[j]);
}

/* r = det of the row-major 3x3 matrix a. */
static void det3(mpz_t r, mpz_srcptr a[9])
{
    mpz_t t;
    mpz_init(t);
    mpz_mul(t, a[4], a[8]);
    mpz_submul(t, a[5], a[7]);
    mpz_mul(r, a[0], t);
    mpz_mul(t, a[3], a[8]);
    mpz_submul(t, a[5], a[6]);
    mpz_submul(r, a[1], t);
    mpz_mul(t, a[3], a[7]);
    mpz_submul(t, a[4], a[6]);
    mpz_addmul(r, a[2], t);
    mpz_clear(t);
}

/* r = det of the row-major 4x4 matrix a, by expansion along the last column. */
static void det4(mpz_t r, mpz_srcptr a[16])
{
    mpz_t minor;
    mpz_init(minor);
    mpz_set_ui(r, 0);
    for (int i = 0; i < 4; i++) {
        mpz_srcptr m[9];
        int k = 0;
        for (int row = 0; row < 4; row++) {
            if (row == i) continue;
            for (int col = 0; col < 3; col++) m[k++] = a[4 * row + col];
        }
        det3(minor, m);
        /* cofactor sign of entry (i, 3): (-1)^(i+3) */
        if ((i + 3) % 2 == 0)
            mpz_addmul(r, a[4 * i + 3], minor);
        else
            mpz_submul(r, a[4 * i + 3], minor);
    }
    mpz_clear(minor);
}

/* sign det[q-p; r-p; s-p] */
static int z_orient3d(const zpt *p, const zpt *q, const zpt *r, const zpt *s)
{
    mpz_t d[9], det;
    mpz_srcptr m[9];
    const zpt *rows[3] = {q, r, s};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            mpz_init(d[3 * i + j]);
            mpz_sub(d[3 * i + j], rows[i]->c[j], p->c[j]);
            m[3 * i + j] = d[3 * i + j];
        }
    mpz_init(det);
    det3(det, m);
    int s_ = mpz_sgn(det);
    mpz_clear(det);
    for (int i = 0; i < 9; i++) mpz_clear(d[i]);
    return s_;
}

/* +1 when e is inside the sphere of the positively oriented (a,b,c,d); see the top. */
static int z_insphere(const zpt *a, const zpt *b, const zpt *c, const zpt *d, const zpt *e)
{
    mpz_t m[16], det;
    mpz_srcptr mp[16];
    const zpt *rows[4] = {a, b, c, d};
    for (int i = 0; i < 4; i++) {
        mpz_init(m[4 * i + 3]);
        for (int j = 0; j < 3; j++) {
            mpz_init(m[4 * i + j]);
            mpz_sub(m[4 * i + j], rows[i]->c[j], e->c[j]);
            mpz_addmul(m[4 * i + 3], m[4 * i + j], m[4 * i + j]);
        }
    }
    for (int i = 0; i < 16; i++) mp[i] = m[i];
    mpz_init(det);
    det4(det, mp);
    int s = -mpz_sgn(det);
    mpz_clear(det);
    for (int i = 0; i < 16; i++) mpz_clear(m[i]);
    return s;
}

/* The two coordinate axes kept when dropping drop_axis: 2 -> (x,y), 0 -> (y,z), 1 -> (x,z),
 * CGAL's orientationC2 on (px,py), (py,pz), (px,pz). */
static void proj_axes(int drop_axis, int *i, int *j)
{
    *i = drop_axis == 0 ? 1 : 0;
    *j = drop_axis == 2 ? 1 : 2;
}

/* sign((q_i-p_i)(r_j-p_j) - (q_j-p_j)(r_i-p_i)), CGAL's orientationC2 in the projection. */
static int z_orient2d_proj(const zpt *p, const zpt *q, const zpt *r, int drop_axis)
{
    int i, j;
    proj_axes(drop_axis, &i, &j);
    mpz_t a, b, c, d;
    mpz_inits(a, b, c, d, NULL);
    mpz_sub(a, q->c[i], p->c[i]);
    mpz_sub(b, r->c[j], p->c[j]);
    mpz_sub(c, q->c[j], p->c[j]);
    mpz_sub(d, r->c[i], p->c[i]);
    mpz_mul(a, a, b);
    mpz_submul(a, c, d);
    int s = mpz_sgn(a);
    mpz_clears(a, b, c, d, NULL);
    return s;
}

/* CGAL's coplanar_orientationC3(p,q,r): the xy projection, else yz, else xz. */
static int z_coplanar_orientation(const zpt *p, const zpt *q, const zpt *r)
{
    int o = z_orient2d_proj(p, q, r, 2);
    if (o != 0) return o;
    o = z_orient2d_proj(p, q, r, 0);
    if (o != 0) return o;
    return z_orient2d_proj(p, q, r, 1);
}

/* CGAL's coplanar_side_of_bounded_circleC3(p,q,r,t): +1 inside the circle through p,q,r (in
 * their plane), computed as the sign of the 4x4 determinant with rows
 * (p-t, |p-t|^2), (r-t, |r-t|^2), (q-t, |q-t|^2), (v, |v|^2), v = (q-p) x (r-p),
 * transcribed in that row order. */
static int z_coplanar_side_of_bounded_circle(const zpt *p, const zpt *q, const zpt *r,
                                             const zpt *t)
{
    mpz_t m[16], pq[3], pr[3], det;
    mpz_srcptr mp[16];
    const zpt *rows[3] = {p, r, q};
    for (int i = 0; i < 16; i++) mpz_init(m[i]);
    for (int j = 0; j < 3; j++) {
        mpz_init(pq[j]);
        mpz_init(pr[j]);
        mpz_sub(pq[j], q->c[j], p->c[j]);
        mpz_sub(pr[j], r->c[j], p->c[j]);
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            mpz_sub(m[4 * i + j], rows[i]->c[j], t->c[j]);
            mpz_addmul(m[4 * i + 3], m[4 * i + j], m[4 * i + j]);
        }
    /* v = pq x pr */
    mpz_mul(m[12], pq[1], pr[2]);
    mpz_submul(m[12], pq[2], pr[1]);
    mpz_mul(m[13], pq[2], pr[0]);
    mpz_submul(m[13], pq[0], pr[2]);
    mpz_mul(m[14], pq[0], pr[1]);
    mpz_submul(m[14], pq[1], pr[0]);
    for (int j = 0; j < 3; j++) mpz_addmul(m[15], m[12 + j], m[12 + j]);
    for (int i = 0; i < 16; i++) mp[i] = m[i];
    mpz_init(det);
    det4(det, mp);
    int s = mpz_sgn(det);
    mpz_clear(det);
    for (int i = 0; i < 16; i++) mpz_clear(m[i]);
    for (int j = 0; j < 3; j++) {
        mpz_clear(pq[j]);
        mpz_clear(pr[j]);
    }
    return s;
}

int orc_lex_compare(const double *p, const double *q)
{
    for (int j = 0; j < 3; j++) {
        if (p[j] < q[j]) return -1;
        if (p[j] > q[j]) return 1;
    }
    return 0;
}

/* order[0..k-1] = 0..k-1 sorted by increasing lexicographic rank of pts[] (insertion sort,
 * stable, so equal points keep their argument order). */
static void lex_order(const double *const *pts, int k, int *order)
{
    for (int i = 0; i < k; i++) order[i] = i;
    for (int i = 1; i < k; i++) {
        int v = order[i], j = i;
        while (j > 0 && orc_lex_compare(pts[order[j - 1]], pts[v]) > 0) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = v;
    }
}

int orc_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    const double *p[4] = {a, b, c, d};
    orc_small sm;
    if (orc_small_load(&sm, p, 4)) return orc_small_orient3d(sm.c[0], sm.c[1], sm.c[2], sm.c[3]);
    zpt z[4];
    load(z, p, 4);
    int s = z_orient3d(&z[0], &z[1], &z[2], &z[3]);
    unload(z, 4);
    return s;
}

int orc_insphere(const double *a, const double *b, const double *c, const double *d,
                 const double *e)
{
    const double *p[5] = {a, b, c, d, e};
    orc_small sm;
    if (orc_small_load(&sm, p, 5))
        return orc_small_insphere(sm.c[0], sm.c[1], sm.c[2], sm.c[3], sm.c[4]);
    zpt z[5];
    load(z, p, 5);
    int s = z_insphere(&z[0], &z[1], &z[2], &z[3], &z[4]);
    unload(z, 5);
    return s;
}

int orc_orient2d_proj(const double *a, const double *b, const double *c, int drop_axis)
{
    const double *p[3] = {a, b, c};
    zpt z[3];
    load(z, p, 3);
    int s = z_orient2d_proj(&z[0], &z[1], &z[2], drop_axis);
    unload(z, 3);
    return s;
}

int orc_coplanar_orientation(const double *a, const double *b, const double *c)
{
    const double *p[3] = {a, b, c};
    zpt z[3];
    load(z, p, 3);
    int s = z_coplanar_orientation(&z[0], &z[1], &z[2]);
    unload(z, 3);
    return s;
}

/* Five loaded points, on the small-integer path or as mpz. */
typedef struct pset {
    const orc_small *sm;  /* NULL: use z */
    const zpt *z;
} pset;

static int pset_orient3d(const pset *s, const int q[4])
{
    if (s->sm)
        return orc_small_orient3d(s->sm->c[q[0]], s->sm->c[q[1]], s->sm->c[q[2]], s->sm->c[q[3]]);
    return z_orient3d(&s->z[q[0]], &s->z[q[1]], &s->z[q[2]], &s->z[q[3]]);
}

/* CGAL's side_of_oriented_sphere(p0,p1,p2,p3,p, perturb=true) for a POSITIVELY oriented
 * (p0,p1,p2,p3) whose exact insphere is 0.  role[i] is the index of p_i among the five loaded
 * points, p is index 4; pts the doubles (for the ranking).  Sort the five by lexicographic
 * rank; for the highest, then the second highest point: if it is p, the answer is -1 (p0..p3
 * positive); if it is p_i, the answer is the orientation of (p0,p1,p2,p3) with p_i replaced by
 * p, when that is nonzero.  Two ranks always decide for distinct points (Devillers & Teillaud
 * 2011); CGAL returns -1 if not, so do we. */
static int sos_insphere_positive(const pset *s, const int role[4], const double *const *pts)
{
    const double *rp[5] = {pts[role[0]], pts[role[1]], pts[role[2]], pts[role[3]], pts[4]};
    int order[5];
    lex_order(rp, 5, order);
    for (int i = 4; i > 2; i--) {
        int w = order[i];
        if (w == 4) return -1;
        int q[4] = {role[0], role[1], role[2], role[3]};
        q[w] = 4;                                 /* p replaces p_w in its slot */
        int o = pset_orient3d(s, q);
        if (o != 0) return o;
    }
    return -1;
}

/* The sign flips with the orientation: a negative (a,b,c,d) is evaluated as the positive
 * (b,a,c,d) and negated. */
static int insphere_sos_set(const pset *s, int exact, const double *const *pts)
{
    static const int pos[4] = {0, 1, 2, 3}, neg[4] = {1, 0, 2, 3};
    if (exact != 0) return exact;
    int o = pset_orient3d(s, pos);
    if (o > 0) return sos_insphere_positive(s, pos, pts);
    if (o < 0) return -sos_insphere_positive(s, neg, pts);
    return 0;  /* precondition violated: the exact 0 is the honest answer */
}

int orc_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                     const double *e)
{
    const double *p[5] = {a, b, c, d, e};
    orc_small sm;
    if (orc_small_load(&sm, p, 5)) {
        pset s = {&sm, NULL};
        return insphere_sos_set(&s, orc_small_insphere(sm.c[0], sm.c[1], sm.c[2], sm.c[3], sm.c[4]), p);
    }
    zpt z[5];
    load(z, p, 5);
    pset s = {NULL, z};
    int r = insphere_sos_set(&s, z_insphere(&z[0], &z[1], &z[2], &z[3], &z[4]), p);
    unload(z, 5);
    return r;
}

/* CGAL's coplanar_side_of_bounded_circle(p0,p1,p2,p, perturb=true), with p coplanar with the
 * non-collinear p0,p1,p2: the exact sign if nonzero; else sort the four by rank and walk down
 * from the highest (three ranks): p -> -1; p_i -> coplanar_orientation of (p0,p1,p2) with p_i
 * replaced by p, times local = coplanar_orientation(p0,p1,p2), when nonzero; else -local. */
static int z_circle_sos(const zpt *z, const double *const *pts)
{
    int s = z_coplanar_side_of_bounded_circle(&z[0], &z[1], &z[2], &z[3]);
    if (s != 0) return s;
    int order[4];
    lex_order(pts, 4, order);
    int local = z_coplanar_orientation(&z[0], &z[1], &z[2]);
    for (int i = 3; i > 0; i--) {
        int w = order[i];
        if (w == 3) return -1;
        const zpt *q[3] = {&z[0], &z[1], &z[2]};
        q[w] = &z[3];
        int o = z_coplanar_orientation(q[0], q[1], q[2]);
        if (o != 0) return o * local;
    }
    return -local;
}

int orc_coplanar_circle_sos(const double *a, const double *b, const double *c, const double *e)
{
    const double *p[4] = {a, b, c, e};
    zpt z[4];
    load(z, p, 4);
    int s = z_coplanar_orientation(&z[0], &z[1], &z[2]) == 0 ? 0 : z_circle_sos(z, p);
    unload(z, 4);
    return s;
}

/* CGAL's side_of_sphere for the infinite cell (a,b,c,inf): o = orientation(a,b,c,e); if
 * nonzero it is the answer (+1: e beyond the hull facet, in conflict); if e is coplanar, the
 * perturbed coplanar_side_of_bounded_circle(a,b,c,e). */
int orc_ghost_conflict(const double *a, const double *b, const double *c, const double *e)
{
    const double *p[4] = {a, b, c, e};
    zpt z[4];
    load(z, p, 4);
    int s = z_orient3d(&z[0], &z[1], &z[2], &z[3]);
    if (s == 0)
        s = z_coplanar_orientation(&z[0], &z[1], &z[2]) == 0 ? 0 : z_circle_sos(z, p);
    unload(z, 4);
    return s;
}

/* sign det[B-A; C-A; D-A] where A, B, C, D are centroids of cnt[0..3] (1..4) points listed
 * one after the other in pts.  Each centroid is represented exactly as 12 * centroid =
 * (12/cnt) * (sum of its points); scaling all four by 12 keeps the sign (degree 3). */
int orc_orient3d_avg(const double *const *pts, const int cnt[4])
{
    int k = 0;
    for (int i = 0; i < 4; i++) {
        if (cnt[i] < 1 || cnt[i] > 4) return 0;
        k += cnt[i];
    }
    zpt z[ORC_MAX_LOAD], c[4];
    load(z, pts, k);
    int at = 0;
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 3; j++) {
            mpz_init(c[i].c[j]);
            for (int u = 0; u < cnt[i]; u++) mpz_add(c[i].c[j], c[i].c[j], z[at + u].c[j]);
            mpz_mul_ui(c[i].c[j], c[i].c[j], (unsigned long)(12 / cnt[i]));
        }
        at += cnt[i];
    }
    int s = z_orient3d(&c[0], &c[1], &c[2], &c[3]);
    unload(c, 4);
    unload(z, k);
    return s;
}

/* One double as an integer at the global scale 2^-emin. */
static void scaled(mpz_t r, double x, int emin)
{
    double m;
    int e;
    orc_split_double(x, &m, &e);
    mpz_set_d(r, m);
    if (m != 0.0) mpz_mul_2exp(r, r, (mp_bitcnt_t)(e - emin));
}

/* Sum over the tets of det[b-a; c-a; d-a] (6 * volume) compared with the sum over the hull
 * facets of det[a; b; c] (6 * the volume enclosed, by the divergence theorem, for outward
 * oriented facets), both exact at one global power-of-two scale: returns the sign of
 * (tets - hull), 0 when equal. */
__extension__ typedef __int128 vi128;
__extension__ typedef unsigned __int128 vu128;

/* A 256-bit unsigned accumulator (little-endian 64-bit limbs): a += x * 2^(64k), k <= 1. */
static void acc_add(uint64_t a[4], vu128 x, int k)
{
    vu128 s = (vu128)a[k] + (uint64_t)x;
    a[k] = (uint64_t)s;
    s = (vu128)a[k + 1] + (uint64_t)(x >> 64) + (uint64_t)(s >> 64);
    a[k + 1] = (uint64_t)s;
    uint64_t carry = (uint64_t)(s >> 64);
    for (int i = k + 2; i < 4 && carry; i++) {
        a[i] += carry;
        carry = a[i] == 0;
    }
}

/* pos or neg += u * m (|u| < 2^62, |m| < 2^125): a product below 2^187, added as two parts. */
static void acc_term(uint64_t pos[4], uint64_t neg[4], int64_t u, vi128 m)
{
    if (u == 0 || m == 0) return;
    uint64_t *a = (u < 0) != (m < 0) ? neg : pos;
    uint64_t au = u < 0 ? (uint64_t)(-u) : (uint64_t)u;
    vu128 am = m < 0 ? (vu128)(-m) : (vu128)m;
    acc_add(a, (vu128)au * (uint64_t)am, 0);
    acc_add(a, (vu128)au * (uint64_t)(am >> 64), 1);
}

/* x * 2^-emin as an int64 in *r when it is below 2^61 in magnitude (it is an integer: emin is
 * at most the exponent of x's last bit); 0 when it is larger. */
static int scaled_small(double x, int emin, int64_t *r)
{
    double s = ldexp(x, -emin);  /* exact: a power-of-two scaling to an integer, or inf */
    if (!(fabs(s) < 0x1p61)) return 0;
    *r = (int64_t)s;
    return 1;
}

/* sum += det[b-a; c-a; d-a] over tets [lo, hi), coordinates scaled by 2^-emin.  A tet whose
 * scaled coordinates are below 2^61 is summed in fixed-width integers: differences below 2^62
 * (int64), 2x2 minors below 2^125 (vi128), each of the three terms of the determinant below
 * 2^187, accumulated by sign in two 256-bit accumulators (fewer than 3 * 2^30 terms: below
 * 2^219, no overflow), added to sum at the end.  The other tets go through mpz.  Both are
 * exact, so the sum is the same either way. */
static void volume_sum_tets(mpz_t sum, const double *vertices, const uint32_t *tets, size_t lo,
                            size_t hi, int emin, int (*stop)(void *, size_t), void *stop_user)
{
    mpz_t det, p[4][3], d[9];
    mpz_init(det);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) mpz_init(p[i][j]);
    for (int i = 0; i < 9; i++) mpz_init(d[i]);
    mpz_srcptr m[9];
    for (int i = 0; i < 9; i++) m[i] = d[i];
    uint64_t pos[4] = {0, 0, 0, 0}, neg[4] = {0, 0, 0, 0};
    for (size_t t = lo; t < hi; t++) {
        if (stop && stop(stop_user, t - lo)) break;  /* the sum is then of no use */
        int64_t q[4][3];
        int small = 1;
        for (int i = 0; i < 4 && small; i++)
            for (int j = 0; j < 3 && small; j++)
                small = scaled_small(vertices[3 * (size_t)tets[4 * t + i] + j], emin, &q[i][j]);
        if (small) {
            int64_t u[3], v[3], w[3];
            for (int j = 0; j < 3; j++) {
                u[j] = q[1][j] - q[0][j];
                v[j] = q[2][j] - q[0][j];
                w[j] = q[3][j] - q[0][j];
            }
            vi128 m0 = (vi128)v[1] * w[2] - (vi128)v[2] * w[1];
            vi128 m1 = (vi128)v[0] * w[2] - (vi128)v[2] * w[0];
            vi128 m2 = (vi128)v[0] * w[1] - (vi128)v[1] * w[0];
            acc_term(pos, neg, u[0], m0);
            acc_term(pos, neg, -u[1], m1);
            acc_term(pos, neg, u[2], m2);
            continue;
        }
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 3; j++) scaled(p[i][j], vertices[3 * (size_t)tets[4 * t + i] + j], emin);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) mpz_sub(d[3 * i + j], p[i + 1][j], p[0][j]);
        det3(det, m);
        mpz_add(sum, sum, det);
    }
    mpz_import(det, 4, -1, sizeof pos[0], 0, 0, pos);
    mpz_add(sum, sum, det);
    mpz_import(det, 4, -1, sizeof neg[0], 0, 0, neg);
    mpz_sub(sum, sum, det);
    mpz_clear(det);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) mpz_clear(p[i][j]);
    for (int i = 0; i < 9; i++) mpz_clear(d[i]);
}

/* The tets' sum is split over OpenMP threads: each adds a contiguous range into its own mpz,
 * and the partial sums are added under a critical section.  Integer addition is exact and
 * associative, so the total (and the sign returned) does not depend on the thread count or
 * the order of the additions. */
int orc_compare_volume(const double *vertices, size_t nv, const uint32_t *tets, size_t nt,
                       const uint32_t *hull, size_t nh, int threads,
                       int (*stop)(void *user, size_t i), void *stop_user)
{
    int emin = INT_MAX;
#pragma omp parallel for num_threads(threads) reduction(min : emin) schedule(static) \
    if (nv > 65536)
    for (size_t i = 0; i < 3 * nv; i++) {
        double m;
        int e;
        orc_split_double(vertices[i], &m, &e);
        if (m != 0.0 && e < emin) emin = e;
    }
    if (emin == INT_MAX) emin = 0;
    mpz_t sum, det, d[9];
    mpz_inits(sum, det, NULL);
    for (int i = 0; i < 9; i++) mpz_init(d[i]);
    mpz_srcptr m[9];
    for (int i = 0; i < 9; i++) m[i] = d[i];
#pragma omp parallel num_threads(threads) if (nt > 16384)
    {
        mpz_t part;
        mpz_init(part);
        int nth = omp_get_num_threads(), me = omp_get_thread_num();
        size_t lo = nt * (size_t)me / (size_t)nth, hi = nt * (size_t)(me + 1) / (size_t)nth;
        volume_sum_tets(part, vertices, tets, lo, hi, emin, stop, stop_user);
#pragma omp critical(gtet_orc_volume)
        mpz_add(sum, sum, part);
        mpz_clear(part);
    }
    for (size_t h = 0; h < nh; h++) {
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) scaled(d[3 * i + j], vertices[3 * (size_t)hull[3 * h + i] + j], emin);
        det3(det, m);
        mpz_sub(sum, sum, det);
    }
    int s = mpz_sgn(sum);
    mpz_clears(sum, det, NULL);
    for (int i = 0; i < 9; i++) mpz_clear(d[i]);
    return s;
}
