/* pred.h -- internal interface of the geometric predicates (prefix pred_).
 *
 * Every sign the kernel uses comes from here.  Each predicate is one readable chain:
 *   1. semi-static filter in double on translated coordinates (constants certified in proofs/),
 *   2. exact stage: small-integer path (int64/__int128), the 60-bit integer form of the tuple
 *      in fixed-width 128/192/320-bit arithmetic, expansion arithmetic (Shewchuk 1997, our own
 *      code) in a magnitude band, and GMP mpz on the exact integer form for everything else,
 *   3. symbolic perturbation of exact zeros (lexicographic rank, CGAL's rule; see
 *      proofs/perturbation.md).
 * Counters are passed explicitly (one record per worker thread): no global mutable state.
 * Conventions are those of gigatet.h: orient3d = sign det[b-a; c-a; d-a], insphere > 0 when e
 * is inside the sphere of a positively oriented (a,b,c,d).
 * Points are `const double *` to three consecutive coordinates (only those three are read;
 * the kernel stores 3 doubles per vertex).
 */
#ifndef GTET_PRED_H
#define GTET_PRED_H

#include "gigatet.h"
#include "filter.h"
#include "fpenv.h"

/* Counters: every function below takes a non-NULL pred_counters* (one record per thread; the
 * increments are plain, unsynchronised adds) and counts each call and how it was decided:
 * *_calls, *_exact (filter undecided), *_int (small-integer stage), *_gmp (GMP stage; the
 * rest of *_exact went through expansions), *_zero (exact zero), sos_calls / sos_depth.
 * The perturbation's own orient3d evaluations are counted as orient3d calls; the 2D
 * orientations of the coplanar circle rule are not counted. */
typedef gtet_pred_counters pred_counters;

/* Exact sign of orient3d (0 possible). */
int pred_orient3d(const double *a, const double *b, const double *c, const double *d,
                  pred_counters *cnt);

/* Exact sign of insphere (0 possible). */
int pred_insphere(const double *a, const double *b, const double *c, const double *d,
                  const double *e, pred_counters *cnt);

/* For a caller that inlines the filter (filter.h) itself, e.g. the kernel's cavity test:
 *     cnt->insphere_calls++;
 *     int s = pred_insphere_filter(a, b, c, d, e, PRED_NO_STATIC, NULL);
 *     if (s == 0) s = pred_insphere_exact(a, b, c, d, e, cnt);
 * is exactly pred_insphere (same for orient3d).  The _exact functions count *_exact and
 * the stage / zero counters, not *_calls. */
int pred_orient3d_exact(const double *a, const double *b, const double *c, const double *d,
                        pred_counters *cnt);
int pred_insphere_exact(const double *a, const double *b, const double *c, const double *d,
                        const double *e, pred_counters *cnt);

/* What the predicates may assume about a whole point set (static.c, proofs/filters.md
 * sections 8 and 9): the filters' static bounds on the set's extents, and whether the set is a
 * lattice small enough for the filter's evaluation to be exact (then the bound is 0 and an
 * undecided filter means an exact zero).  Only valid for points of the set it was made from. */
#define PRED_O3_LATTICE_E 114501.0  /* largest E with 6 E^3 <= 2^53 */
#define PRED_IS_LATTICE_E 659.0     /* largest E with 72 E^5 <= 2^53 */
typedef struct pred_static {
    double o3_seps, is_seps;   /* static bounds (0 when exact), or PRED_NO_STATIC */
    int o3_exact, is_exact;    /* the filter's det~ is the exact determinant */
    int int23;                 /* every coordinate is an integer of magnitude < 2^23: the
                                  small-integer insphere stage applies to every tuple */
} pred_static;
extern const pred_static pred_static_none;
void pred_static_init(const double *xyz, size_t stride, size_t n, pred_static *ps);
/* The same on `threads` threads (OpenMP; the scan is a reduction, the result is the same);
 * box, unless NULL, receives the points' bounding box (min x, y, z, max x, y, z; zeros for
 * n == 0), which the scan computes anyway. */
void pred_static_init_mt(const double *xyz, size_t stride, size_t n, int threads,
                         pred_static *ps, double box[6]);

/* orient3d for points of ps's set: filter with its static bound, then the exact stage unless
 * the lattice makes the filter exact.  _rest: the part after a caller's inline
 * pred_orient3d_filter(..., ps->o3_seps) was undecided (it does not count the call). */
int pred_orient3d_st(const double *a, const double *b, const double *c, const double *d,
                     const pred_static *ps, pred_counters *cnt);
int pred_orient3d_rest(const double *a, const double *b, const double *c, const double *d,
                       const pred_static *ps, pred_counters *cnt);

/* The perturbed insphere for points of ps's set after the caller's inline
 * pred_insphere_filter(..., ps->is_seps, minors) was undecided; counts the call.  minors: what
 * that filter reported (PRED_IS_NMINORS doubles; used when ps->is_exact, and on a set of small
 * integers when its record shows an exact evaluation; may be NULL unless ps->is_exact).  Same
 * answer as pred_insphere_sos. */
int pred_insphere_sos_rest(const double *a, const double *b, const double *c, const double *d,
                           const double *e, const pred_static *ps, const double *minors,
                           pred_counters *cnt);

/* Perturbed insphere: equals pred_insphere when that is non-zero; never 0 for five distinct
 * points with orient3d(a,b,c,d) != 0; CGAL's side_of_oriented_sphere(perturb) when
 * orient3d(a,b,c,d) > 0, and antisymmetric in (a,b,c,d) (see sos.c). */
int pred_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                      const double *e, pred_counters *cnt);

/* Hull rule (see gtet_ghost_conflict): +1 if e conflicts with ghost tet (a,b,c,inf). */
int pred_ghost_conflict(const double *a, const double *b, const double *c, const double *e,
                        pred_counters *cnt);

/* A record of the perturbation's decisions (gtet_options.degeneracies), one per thread: the
 * functions below append to it without synchronisation.  Every decision counted in
 * cnt->sos_calls adds one to `total` and, while fewer than `limit` are stored, one record:
 * its kind, the points' ids in the predicate's argument order (a point's id is its index in
 * base, 3 doubles per point), the term that decided (1-based: the one counted in
 * sos_depth[term-1]) and the sign returned. */
typedef struct pred_sos_log {
    const double *base;     /* the point set every recorded point belongs to */
    size_t nv;              /* its points */
    size_t limit;           /* records stored at most */
    gtet_degeneracy *rec;   /* the first min(total, limit) decisions, in the order made */
    size_t n, cap;
    uint64_t total;         /* decisions made */
    int failed;             /* 0, or the bits PRED_SOS_LOG_NOMEM (an allocation failed:
                               records were lost) and PRED_SOS_LOG_FOREIGN (a point was not
                               one of base's: its id is UINT32_MAX) */
} pred_sos_log;
#define PRED_SOS_LOG_NOMEM 1
#define PRED_SOS_LOG_FOREIGN 2

/* Append one decision (called by the functions below when their log is not NULL). */
void pred_sos_log_add(pred_sos_log *log, int kind, const double *const *p, int np, int term,
                      int sign);

/* pred_insphere_sos_rest and pred_ghost_conflict that record their perturbation's decisions
 * in log (NULL: the same as those, at the cost of one untaken branch per decision). */
int pred_insphere_sos_rest_log(const double *a, const double *b, const double *c,
                               const double *d, const double *e, const pred_static *ps,
                               const double *minors, pred_counters *cnt, pred_sos_log *log);
int pred_ghost_conflict_log(const double *a, const double *b, const double *c,
                            const double *e, pred_counters *cnt, pred_sos_log *log);
/* The same for points of ps's set: its orient3d with the static bound and lattice exactness
 * (pred_orient3d_st); the same answer (NOTES.md E31). */
int pred_ghost_conflict_st_log(const double *a, const double *b, const double *c,
                               const double *e, const pred_static *ps, pred_counters *cnt,
                               pred_sos_log *log);

/* Perturbed in-circle of e against the circle through a,b,c in their common plane (all four
 * coplanar): +1 inside, -1 outside, never 0 for distinct points with a,b,c not collinear. */
int pred_incircle_coplanar_sos(const double *a, const double *b, const double *c,
                               const double *e, pred_counters *cnt);

/* Lexicographic (x, then y, then z) comparison: -1, 0, +1.  -0.0 == +0.0. */
static inline int pred_lex_cmp(const double *p, const double *q)
{
    /* branch-free: on lattices the coordinates tie often and branches mispredict */
    const int cx = (p[0] > q[0]) - (p[0] < q[0]);
    const int cy = (p[1] > q[1]) - (p[1] < q[1]);
    const int cz = (p[2] > q[2]) - (p[2] < q[2]);
    return cx ? cx : cy ? cy : cz;
}

/* Run-time check of the floating-point assumptions the filters' proofs rely on (binary64,
 * round-to-nearest, no contraction of a*b+c, no extended precision).  0 when they hold; else a
 * bit mask of what failed (see fpenv.h). */
int pred_fp_selftest(void);

/* CGAL's coplanar_orientation(a,b,c): the orientation of (a,b,c) in the first of the xy, yz,
 * xz projections where it is not collinear; 0 exactly when a,b,c are collinear. */
int pred_coplanar_orientation(const double *a, const double *b, const double *c,
                              pred_counters *cnt);

#endif
