/* test_check_meshes.h -- small meshes for the checker's tests, built without the kernel.
 *
 * tm_brute_delaunay() is the definition of the perturbed Delaunay tetrahedrization turned into
 * code: every 4-subset of the points, oriented positively, whose perturbed circumsphere
 * (orc_insphere_sos) contains no other point.  O(n^5), for a dozen or two points.
 * tm_neighbors() matches facets by brute force (O(m^2)), independently of the checker's sort.
 */
#ifndef GTET_TEST_CHECK_MESHES_H
#define GTET_TEST_CHECK_MESHES_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "canon.h"
#include "gigatet.h"
#include "oracle/oracle.h"

typedef struct tmesh {
    double *v;      /* 3*nv */
    size_t nv;
    uint32_t *t;    /* 4*nt */
    size_t nt;
    uint32_t *nb;   /* 4*nt */
} tmesh;

static inline void tm_free(tmesh *m)
{
    free(m->v);
    free(m->t);
    free(m->nb);
    memset(m, 0, sizeof *m);
}

/* Orient tet (a,b,c,d) positively in place (swap c and d when negative). */
static inline void tm_orient(const double *v, uint32_t *t)
{
    if (orc_orient3d(v + 3 * t[0], v + 3 * t[1], v + 3 * t[2], v + 3 * t[3]) < 0) {
        uint32_t x = t[2];
        t[2] = t[3];
        t[3] = x;
    }
}

/* neighbors by brute-force facet matching */
static inline void tm_neighbors(tmesh *m)
{
    size_t nf = 4 * m->nt;
    free(m->nb);
    m->nb = malloc((nf ? nf : 1) * sizeof *m->nb);
    for (size_t i = 0; i < nf; i++) m->nb[i] = GTET_NO_TET;
    for (size_t a = 0; a < m->nt; a++)
        for (size_t b = 0; b < m->nt; b++) {
            if (a == b) continue;
            int shared = 0, fa = -1;
            for (int i = 0; i < 4; i++) {
                int in = 0;
                for (int j = 0; j < 4; j++) in |= m->t[4 * a + i] == m->t[4 * b + j];
                if (in) shared++;
                else fa = i;
            }
            if (shared == 3) m->nb[4 * a + (size_t)fa] = (uint32_t)b;
        }
}

/* Copy points and tets into a mesh (tets oriented positively), neighbors filled. */
static inline tmesh tm_make(const double *v, size_t nv, const uint32_t *t, size_t nt)
{
    tmesh m;
    m.nv = nv;
    m.nt = nt;
    m.v = malloc(3 * nv * sizeof *m.v);
    m.t = malloc(4 * (nt ? nt : 1) * sizeof *m.t);
    m.nb = NULL;
    memcpy(m.v, v, 3 * nv * sizeof *m.v);
    memcpy(m.t, t, 4 * nt * sizeof *m.t);
    for (size_t i = 0; i < nt; i++) tm_orient(m.v, m.t + 4 * i);
    tm_neighbors(&m);
    return m;
}

static inline tmesh tm_brute_delaunay(const double *v, size_t nv)
{
    size_t cap = 64, nt = 0;
    uint32_t *t = malloc(4 * cap * sizeof *t);
    for (uint32_t a = 0; a < nv; a++)
        for (uint32_t b = a + 1; b < nv; b++)
            for (uint32_t c = b + 1; c < nv; c++)
                for (uint32_t d = c + 1; d < nv; d++) {
                    uint32_t q[4] = {a, b, c, d};
                    if (orc_orient3d(v + 3 * a, v + 3 * b, v + 3 * c, v + 3 * d) == 0) continue;
                    tm_orient(v, q);
                    int empty = 1;
                    for (uint32_t e = 0; e < nv && empty; e++) {
                        if (e == a || e == b || e == c || e == d) continue;
                        empty = orc_insphere_sos(v + 3 * q[0], v + 3 * q[1], v + 3 * q[2],
                                                 v + 3 * q[3], v + 3 * e) == -1;
                    }
                    if (!empty) continue;
                    if (nt == cap) t = realloc(t, 4 * (cap *= 2) * sizeof *t);
                    memcpy(t + 4 * nt++, q, sizeof q);
                }
    tmesh m = tm_make(v, nv, t, nt);
    free(t);
    return m;
}

/* Same set of tets (as vertex sets)? */
static inline int tm_same_tets(const tmesh *a, const tmesh *b)
{
    if (a->nt != b->nt) return 0;
    uint32_t *x = malloc(4 * a->nt * sizeof *x + 1), *y = malloc(4 * b->nt * sizeof *y + 1);
    if (a->nt) {
        memcpy(x, a->t, 4 * a->nt * sizeof *x);
        memcpy(y, b->t, 4 * b->nt * sizeof *y);
    }
    canon_sort_ids(x, a->nt);
    canon_sort_ids(y, b->nt);
    int same = memcmp(x, y, 4 * a->nt * sizeof *x) == 0;
    free(x);
    free(y);
    return same;
}

static inline gtet_status tm_check(const tmesh *m, const double *xyz, size_t n, unsigned flags,
                                   gtet_check_report *r)
{
    return gtet_check_arrays(m->v, m->nv, m->t, m->nt, m->nb, xyz, n, flags, r);
}

/* n points uniform in the unit cube */
static inline double *tm_random_points(uint64_t seed, size_t n)
{
    double *v = malloc(3 * n * sizeof *v);
    uint64_t s = seed;
    for (size_t i = 0; i < 3 * n; i++) {
        uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        v[i] = (double)((z ^ (z >> 31)) >> 11) * 0x1p-53;
    }
    return v;
}

#endif
