/* canon.h -- a tet mesh as a canonical tet list, the form in which the tests, the fuzzers and
 * tests/cgal/gtet_dt.c compare meshes.
 *
 * Two forms; both are independent of the order of the tets and of the vertices inside a tet:
 *   ids          each tet as its 4 vertex ids in increasing order, the list sorted
 *                (canon_sort_ids).  canon_input_ids first renames a gigatet mesh's vertices
 *                to the smallest input index of their point (through gtet_mesh_input_map),
 *                so that meshes of one point set in different input orders compare equal.
 *   coordinates  each tet as its 4 points in lexicographic order, -0.0 written as +0.0 (the
 *                two are one point), the list sorted (canon_coords): compares meshes whatever
 *                their vertex numbering.
 * Header-only (static inline), so that each fuzz target stays one translation unit.
 */
#ifndef GTET_TESTS_CANON_H
#define GTET_TESTS_CANON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "gigatet.h"

static inline int canon_cmp_ids(const void *pa, const void *pb)
{
    const uint32_t *a = pa, *b = pb;
    for (int k = 0; k < 4; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Sort each of the nt 4-tuples of t, then the tuples. */
static inline void canon_sort_ids(uint32_t *t, size_t nt)
{
    for (size_t i = 0; i < nt; i++) {
        uint32_t *q = t + 4 * i;
        for (int a = 1; a < 4; a++)
            for (int b = a; b > 0 && q[b] < q[b - 1]; b--) {
                uint32_t x = q[b];
                q[b] = q[b - 1];
                q[b - 1] = x;
            }
    }
    if (nt) qsort(t, nt, 4 * sizeof *t, canon_cmp_ids);
}

/* The tets of m (built from n input points) in the ids form, each vertex renamed to the
 * smallest orig[i] (i itself when orig is NULL) over the input points i it stands for:
 * malloc'ed, 4 * gtet_mesh_num_tets(m) ids.  NULL when memory runs out or m is inconsistent
 * (the input map names no vertex, or a tet's vertex stands for no input point); why (at
 * least 160 bytes) then says which. */
static inline uint32_t *canon_input_ids(const gtet_mesh *m, const uint32_t *orig, size_t n,
                                        char *why)
{
    size_t nv = gtet_mesh_num_vertices(m), nt = gtet_mesh_num_tets(m);
    const uint32_t *map = gtet_mesh_input_map(m), *tets = gtet_mesh_tets(m);
    uint32_t *first = malloc((nv ? nv : 1) * sizeof *first);
    uint32_t *c = malloc((nt ? 4 * nt : 1) * sizeof *c);
    int ok = first && c;
    if (!ok) snprintf(why, 160, "out of memory");
    for (size_t v = 0; ok && v < nv; v++) first[v] = UINT32_MAX;
    for (size_t i = 0; ok && i < n; i++) {
        uint32_t o = orig ? orig[i] : (uint32_t)i;
        if (map[i] >= nv) {
            snprintf(why, 160, "input map sends point %zu to vertex %u of %zu", i,
                     (unsigned)map[i], nv);
            ok = 0;
        } else if (o < first[map[i]]) {
            first[map[i]] = o;
        }
    }
    for (size_t i = 0; ok && i < 4 * nt; i++) {
        uint32_t v = tets[i];
        if (v >= nv || first[v] == UINT32_MAX) {
            snprintf(why, 160, "tet %zu has vertex %u, not an input point", i / 4, (unsigned)v);
            ok = 0;
        } else {
            c[i] = first[v];
        }
    }
    free(first);
    if (!ok) {
        free(c);
        return NULL;
    }
    canon_sort_ids(c, nt);
    return c;
}

typedef struct canon_tet { double c[12]; } canon_tet;   /* 4 points, x y z each */

static inline int canon_cmp_point(const double *a, const double *b)
{
    for (int i = 0; i < 3; i++)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

static inline int canon_cmp_tet(const void *pa, const void *pb)
{
    const canon_tet *a = pa, *b = pb;
    for (int i = 0; i < 4; i++) {
        int c = canon_cmp_point(a->c + 3 * i, b->c + 3 * i);
        if (c) return c;
    }
    return 0;
}

/* The tets of m in the coordinates form: malloc'ed, gtet_mesh_num_tets(m) entries; NULL when
 * memory runs out. */
static inline canon_tet *canon_coords(const gtet_mesh *m)
{
    size_t nt = gtet_mesh_num_tets(m);
    const uint32_t *t = gtet_mesh_tets(m);
    const double *v = gtet_mesh_vertices(m);
    canon_tet *c = malloc((nt ? nt : 1) * sizeof *c);
    if (!c) return NULL;
    for (size_t i = 0; i < nt; i++) {
        double *q = c[i].c;
        for (int k = 0; k < 4; k++)
            for (int d = 0; d < 3; d++) {
                double x = v[3 * (size_t)t[4 * i + (size_t)k] + (size_t)d];
                q[3 * k + d] = x == 0 ? 0.0 : x;
            }
        for (int a = 1; a < 4; a++)
            for (int b = a; b > 0 && canon_cmp_point(q + 3 * b, q + 3 * (b - 1)) < 0; b--)
                for (int d = 0; d < 3; d++) {
                    double x = q[3 * b + d];
                    q[3 * b + d] = q[3 * (b - 1) + d];
                    q[3 * (b - 1) + d] = x;
                }
    }
    if (nt) qsort(c, nt, sizeof *c, canon_cmp_tet);
    return c;
}

#endif
