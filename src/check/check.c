/* check.c -- gtet_check_arrays(): the exact invariant checker's entry point, its reporting, and
 * the first stage (the mesh's vertex set against the input points).
 *
 * What a passing check proves (the argument is spread over the stages; each stage's file says
 * which part it establishes):
 *   1. (here) the vertices are pairwise distinct finite points, every vertex lies in some tet,
 *      and, when the input is given, the vertex set equals the set of distinct input points;
 *   2. (check_geom.c) every tet is positively oriented;
 *   3. (check_topo.c) every facet lies in one tet (hull) or two tets on opposite sides; the
 *      hull facets form a closed oriented surface; every vertex link is a sphere or a disk;
 *      V - E + F - T = 1;
 *   4. (check_geom.c) the hull surface is locally convex at every edge (the hull rule), the
 *      centroid o of tet 0 is strictly inside every hull facet, and one ray from o crosses the
 *      surface once: then the hull surface is the boundary of a convex body K and the tets tile
 *      K exactly once, i.e. they form a triangulation of conv(vertices);
 *   5. (check_geom.c) every interior facet is locally Delaunay for the perturbed insphere.  The
 *      perturbation is a symbolic lifting (Devillers & Teillaud 2011), so by the Delaunay lemma
 *      (a locally regular triangulation of a point set is regular: Edelsbrunner; De Loera,
 *      Rambau & Santos, Triangulations, ch. 2) the mesh is THE perturbed Delaunay
 *      tetrahedrization of the vertices, the unique one CGAL also builds.
 * The volume comparison and the optional full empty-sphere test are redundant cross-checks.
 * No printing; the first violation is written into the report as one sentence.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../oracle/oracle.h"
#include "check_internal.h"

gtet_status chk_fail(chk_ctx *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->report->message, sizeof c->report->message, fmt, ap);
    va_end(ap);
    c->report->ok = 0;
    return GTET_ERR_CHECK_FAILED;
}

gtet_status chk_oom(chk_ctx *c)
{
    snprintf(c->report->message, sizeof c->report->message,
             "the checker ran out of memory (%zu vertices, %zu tets)", c->nv, c->nt);
    c->report->ok = 0;
    return GTET_ERR_OUT_OF_MEMORY;
}

void chk_outward_facet(const uint32_t *tet, int f, uint32_t o[3])
{
    /* For a positive (v0,v1,v2,v3), (v_i,v_j,v_k,v_f) with i<j<k has the sign of the
     * permutation (i,j,k,f): odd for f = 0, 2 (keep the order), even for f = 1, 3 (reverse). */
    static const int idx[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (int i = 0; i < 3; i++) o[i] = tet[idx[f][i]];
}

typedef struct vkey {
    double x[3];
    uint32_t id;
} vkey;

static int vkey_cmp(const void *pa, const void *pb)
{
    const vkey *a = pa, *b = pb;
    int s = orc_lex_compare(a->x, b->x);
    if (s) return s;
    return (a->id > b->id) - (a->id < b->id);
}

/* The vertex whose point equals p in the sorted keys, or UINT32_MAX. */
static uint32_t find_vertex(const vkey *keys, size_t nv, const double *p)
{
    size_t lo = 0, hi = nv;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int s = orc_lex_compare(keys[mid].x, p);
        if (s == 0) return keys[mid].id;
        if (s < 0) lo = mid + 1;
        else hi = mid;
    }
    return UINT32_MAX;
}

static int finite3(const double *p) { return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]); }

/* Vertex ids, distinct vertices per tet, finite distinct vertices, every vertex used, and the
 * vertex set against the input points. */
gtet_status chk_inputs(chk_ctx *c)
{
    const uint32_t *T = c->tets;
    const double *V = c->vertices;
    if (c->nv < 4) return chk_fail(c, "the mesh has %zu vertices; a tetrahedrization needs 4", c->nv);
    if (c->nt == 0) return chk_fail(c, "the mesh has no tets");
    for (size_t t = 0; t < c->nt; t++)
        for (int i = 0; i < 4; i++) {
            if (T[4 * t + i] >= c->nv)
                return chk_fail(c, "tet %zu has vertex id %u, out of range (%zu vertices)", t,
                                T[4 * t + i], c->nv);
            for (int j = 0; j < i; j++)
                if (T[4 * t + i] == T[4 * t + j])
                    return chk_fail(c, "tet %zu (%u %u %u %u) repeats vertex %u", t, T[4 * t],
                                    T[4 * t + 1], T[4 * t + 2], T[4 * t + 3], T[4 * t + i]);
        }
    for (size_t v = 0; v < c->nv; v++)
        if (!finite3(V + 3 * v)) return chk_fail(c, "vertex %zu has a non-finite coordinate", v);

    gtet_status st = GTET_OK;
    vkey *keys = malloc(c->nv * sizeof *keys);
    uint32_t *first = malloc(c->nv * sizeof *first);  /* first input index of each vertex */
    if (!keys || !first) {
        st = chk_oom(c);
        goto done;
    }
    for (size_t v = 0; v < c->nv; v++) {
        memcpy(keys[v].x, V + 3 * v, sizeof keys[v].x);
        keys[v].id = (uint32_t)v;
        first[v] = UINT32_MAX;
    }
    qsort(keys, c->nv, sizeof *keys, vkey_cmp);
    for (size_t k = 1; k < c->nv; k++)
        if (orc_lex_compare(keys[k - 1].x, keys[k].x) == 0) {
            st = chk_fail(c, "vertices %u and %u are the same point (%.17g, %.17g, %.17g)",
                          keys[k - 1].id, keys[k].id, keys[k].x[0], keys[k].x[1], keys[k].x[2]);
            goto done;
        }
    /* every vertex in some tet (reuse first[] as a mark) */
    for (size_t t = 0; t < 4 * c->nt; t++) first[T[t]] = 0;
    for (size_t v = 0; v < c->nv; v++)
        if (first[v] == UINT32_MAX) {
            st = chk_fail(c, "vertex %zu (%.17g, %.17g, %.17g) is in no tet", v, V[3 * v],
                          V[3 * v + 1], V[3 * v + 2]);
            goto done;
        }
    if (!c->xyz) goto done;
    if (c->n >= UINT32_MAX) {
        st = chk_fail(c, "%zu input points: more than the checker's 32-bit indices hold", c->n);
        goto done;
    }
    for (size_t v = 0; v < c->nv; v++) first[v] = UINT32_MAX;
    uint64_t dups = 0;
    for (size_t i = 0; i < c->n; i++) {
        const double *p = c->xyz + 3 * i;
        if (!finite3(p)) {
            st = chk_fail(c, "input point %zu has a non-finite coordinate", i);
            goto done;
        }
        uint32_t v = find_vertex(keys, c->nv, p);
        if (v == UINT32_MAX) {
            st = chk_fail(c, "input point %zu (%.17g, %.17g, %.17g) is not a vertex of the mesh",
                          i, p[0], p[1], p[2]);
            goto done;
        }
        if (c->input_map && c->input_map[i] != v) {
            st = chk_fail(c, "input_map[%zu] = %u, but input point %zu is vertex %u", i,
                          c->input_map[i], i, v);
            goto done;
        }
        if (first[v] == UINT32_MAX) first[v] = (uint32_t)i;
        else dups++;
    }
    c->report->duplicates = dups;
    for (size_t v = 0; v < c->nv; v++) {
        if (first[v] == UINT32_MAX) {
            st = chk_fail(c, "vertex %zu (%.17g, %.17g, %.17g) is not an input point", v,
                          V[3 * v], V[3 * v + 1], V[3 * v + 2]);
            goto done;
        }
        /* gigatet numbers its vertices in order of first occurrence */
        if (c->input_map && v > 0 && first[v] < first[v - 1]) {
            st = chk_fail(c, "vertex %zu first occurs at input %u, before vertex %zu (input %u): "
                          "vertices are not numbered in order of first occurrence",
                          v, first[v], v - 1, first[v - 1]);
            goto done;
        }
    }
done:
    free(keys);
    free(first);
    return st;
}

gtet_status chk_run(chk_ctx *c)
{
    gtet_status st = chk_inputs(c);
    if (st == GTET_OK) st = chk_orientation(c);
    if (st == GTET_OK) st = chk_facets(c);
    if (st == GTET_OK) st = chk_hull_surface(c);
    if (st == GTET_OK) st = chk_euler_links(c);
    if (st == GTET_OK) st = chk_delaunay(c);
    if (st == GTET_OK) st = chk_hull_convex(c);
    if (st == GTET_OK) st = chk_volume(c);
    if (st == GTET_OK && (c->flags & GTET_CHECK_FULL)) st = chk_full(c);
    if (st == GTET_OK) {
        c->report->ok = 1;
        snprintf(c->report->message, sizeof c->report->message,
                 "ok: %zu vertices, %zu tets, %zu interior facets locally Delaunay, %zu hull "
                 "facets convex, Euler characteristic %d%s",
                 c->nv, c->nt, c->interior_facets, c->nh, c->report->euler,
                 (c->flags & GTET_CHECK_FULL) ? ", every circumsphere empty" : "");
    }
    free(c->adj);
    free(c->hull);
    free(c->hull_tf);
    free(c->hull_adj);
    c->adj = c->hull = c->hull_tf = c->hull_adj = NULL;
    return st;
}

gtet_status gtet_check_arrays(const double *vertices, size_t nv, const uint32_t *tets,
                              size_t nt, const uint32_t *neighbors, const double *xyz,
                              size_t n, unsigned flags, gtet_check_report *report)
{
    gtet_check_report local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    report->tets = nt;
    if ((!vertices && nv) || (!tets && nt) || (!xyz && n) || (flags & ~CHK_KNOWN_FLAGS)) {
        snprintf(report->message, sizeof report->message,
                 "invalid argument: a NULL array with a nonzero count, or unknown flags");
        return GTET_ERR_ARGUMENT;
    }
    if (nv >= UINT32_MAX || nt >= UINT32_MAX / 4) {
        snprintf(report->message, sizeof report->message,
                 "%zu vertices / %zu tets: more than 32-bit ids hold", nv, nt);
        return GTET_ERR_TOO_LARGE;
    }
    chk_ctx c;
    memset(&c, 0, sizeof c);
    c.vertices = vertices;
    c.nv = nv;
    c.tets = tets;
    c.nt = nt;
    c.neighbors = neighbors;
    c.xyz = xyz;
    c.n = xyz ? n : 0;
    c.flags = flags;
    c.report = report;
    return chk_run(&c);
}
