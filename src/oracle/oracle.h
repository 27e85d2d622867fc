/* oracle.h -- the independent exact GMP oracle (prefix orc_).
 *
 * Plain exact rational arithmetic (mpq) on the doubles as given: every double is a rational,
 * so these are the true signs.  It shares no code with src/pred/ (not even the perturbation
 * rule, which is written again here from its specification), so tests and the checker
 * compare two independent implementations.  Slow on purpose-simple code, not fast code.
 */
#ifndef GTET_ORACLE_H
#define GTET_ORACLE_H

int orc_orient3d(const double *a, const double *b, const double *c, const double *d);
int orc_insphere(const double *a, const double *b, const double *c, const double *d,
                 const double *e);
int orc_insphere_sos(const double *a, const double *b, const double *c, const double *d,
                     const double *e);
int orc_ghost_conflict(const double *a, const double *b, const double *c, const double *e);
int orc_orient2d_proj(const double *a, const double *b, const double *c, int drop_axis);

#endif
