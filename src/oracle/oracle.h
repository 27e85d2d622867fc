/* oracle.h -- the independent exact GMP oracle (prefix orc_).
 *
 * Plain exact integer arithmetic (mpz, or __int128 when the scaled coordinates are below 2^22)
 * on the doubles as given, scaled by one common power of two per call: every double is a
 * dyadic rational, so these are the true signs.  It shares no
 * code with src/pred/ (not even the perturbation rule, which is written again here from its
 * specification), so tests and the checker compare two independent implementations.  Slow on
 * purpose-simple code, not fast code.  Conventions: those of gigatet.h (see oracle.c).
 */
#ifndef GTET_ORACLE_H
#define GTET_ORACLE_H

#include <stddef.h>
#include <stdint.h>

/* sign det[b-a; c-a; d-a] */
int orc_orient3d(const double *a, const double *b, const double *c, const double *d);
/* +1: e strictly inside the sphere of (a,b,c,d) when orient3d(a,b,c,d) > 0; flips with it. */
int orc_insphere(const double *a, const double *b, const double *c, const double *d,
                 const double *e);
/* As orc_insphere, zeros broken by CGAL's lexicographic perturbation; 0 only when
 * orient3d(a,b,c,d) == 0. */
int orc_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                     const double *e);
/* The hull rule of gtet_ghost_conflict: +1 when e conflicts with the ghost (a,b,c,inf). */
int orc_ghost_conflict(const double *a, const double *b, const double *c, const double *e);
/* 2D orientation in the projection dropping drop_axis (2 -> xy, 0 -> yz, 1 -> xz), CGAL's
 * orientationC2 on those coordinate pairs. */
int orc_orient2d_proj(const double *a, const double *b, const double *c, int drop_axis);

/* Extensions. */
/* -1 / 0 / +1: lexicographic (x, y, z) order of the values (-0.0 == +0.0). */
int orc_lex_compare(const double *p, const double *q);
/* CGAL's coplanar_orientationC3(a,b,c): xy projection, else yz, else xz; 0 iff collinear. */
int orc_coplanar_orientation(const double *a, const double *b, const double *c);
/* CGAL's perturbed coplanar_side_of_bounded_circle(a,b,c,e) for e in the plane of a,b,c:
 * +1 inside the perturbed circle, -1 outside; 0 when a,b,c are collinear. */
int orc_coplanar_circle_sos(const double *a, const double *b, const double *c, const double *e);
/* sign det[B-A; C-A; D-A] for the centroids A, B, C, D of cnt[0], .., cnt[3] points (1..4
 * each) given one after the other in pts (exact rational centroids). */
int orc_orient3d_avg(const double *const *pts, const int cnt[4]);
/* Sign of (sum over tets of det[b-a; c-a; d-a]) - (sum over hull facets (a,b,c) of
 * det[a; b; c]), exact: 0 when the tets' total volume equals the volume the outward-oriented
 * hull facets enclose.  tets: 4*nt ids, hull: 3*nh ids into vertices (3*nv doubles).
 * threads: the team of its parallel regions (the answer does not depend on it).  stop (may be
 * NULL) is called by every thread of the tets' sum with the index of its next tet within its
 * range; a nonzero answer ends that thread's share early, and the sign returned is then
 * meaningless (the checker's cancel, check_geom.c). */
int orc_compare_volume(const double *vertices, size_t nv, const uint32_t *tets, size_t nt,
                       const uint32_t *hull, size_t nh, int threads,
                       int (*stop)(void *user, size_t i), void *stop_user);

#endif
