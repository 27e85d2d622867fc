/* check.c -- gtet_check_arrays(): the exact invariant checker's entry point, its reporting, and
 * the first stage (the mesh's vertex set against the input points).
 *
 * What a passing check proves (the argument is spread over the stages; each stage's file says
 * which part it establishes):
 *   1. (here) the vertices in tets are pairwise distinct finite points, every vertex lies in
 *      some tet or repeats the point of one that does, and, when the input is given, the
 *      vertex set equals the set of distinct input points (matched by coordinates);
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
 * Closed mode (GTET_CHECK_DELAUNAY) replaces the perturbed signs of 4 and 5 by the plain ones:
 * the hull convex in the weak sense (no hull vertex beyond a neighbouring hull facet's plane;
 * coplanar allowed) and every interior facet locally Delaunay in the closed sense (the apex
 * across it not strictly inside the tet's circumsphere).  Stages 1-3 and 4(b)-(c) are the
 * same, so the tets still tile conv(vertices) with every vertex used.  Lift each vertex p to
 * (p, |p|^2); the piecewise-linear function F on conv(vertices) that interpolates the lifts on
 * each tet is convex across every interior facet (that is what closed local Delaunay says), so
 * F is convex on the convex domain, and the affine function of any tet is <= F everywhere, in
 * particular at every vertex: no vertex is strictly inside any tet's circumsphere, which is the
 * Delaunay property (Delaunay's lemma with ties; Edelsbrunner, Geometry and Topology for Mesh
 * Generation, ch. 1).  Ties are counted (co-spherical facets, coplanar hull edges).
 * GTET_CHECK_ANY_ORIENTATION turns each negative tet positive (check_geom.c) before stage 3.
 * A vertex in no tet is accepted only as a copy of a vertex that is in one: the mesh's point
 * set is unchanged by it, and it takes no part in stages 2-5.
 * The volume comparison and the optional full empty-sphere test are redundant cross-checks.
 * Every sign is exact: the GMP oracle's, first tried in interval arithmetic (check_filter.c,
 * which only returns signs it proves; GTET_CHECK_NO_FILTER skips it).  Linear in the mesh size
 * apart from sorting small per-vertex buckets.  No printing; the first violation is written
 * into the report as one sentence, the same for any thread count.
 */
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/base.h"
#include "../oracle/oracle.h"
#include "check_internal.h"

gtet_status chk_fail(chk_ctx *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->report->message, sizeof c->report->message, fmt, ap);
    va_end(ap);
    c->report->ok = 0;
    c->report->violation.stage = c->stage;
    return GTET_ERR_CHECK_FAILED;
}

int chk_poll(chk_ctx *c)
{
    if (!c->cancel) return 0;
    if (__atomic_load_n(&c->cancelled, __ATOMIC_RELAXED)) return 1;
    const int level = omp_get_level();
    if (level != c->level && (level != c->level + 1 || omp_get_thread_num() != 0)) return 0;
    if (!c->cancel(c->cancel_user)) return 0;
    __atomic_store_n(&c->cancelled, 1, __ATOMIC_RELAXED);
    return 1;
}

gtet_status chk_cancelled(chk_ctx *c)
{
    gtet_check_report *r = c->report;
    snprintf(r->message, sizeof r->message, "cancelled during the %s stage: no verdict",
             c->stage);
    r->ok = 0;
    memset(&r->violation, 0, sizeof r->violation);
    r->violation.stage = "cancelled";
    r->violation.tet[0] = r->violation.tet[1] = GTET_CHECK_NONE;
    return GTET_ERR_CANCELLED;
}

gtet_status chk_oom(chk_ctx *c)
{
    snprintf(c->report->message, sizeof c->report->message,
             "the checker ran out of memory (%zu vertices, %zu tets)", c->nv, c->nt);
    c->report->ok = 0;
    return GTET_ERR_OUT_OF_MEMORY;
}

void chk_note(chk_ctx *c, uint64_t t0, uint64_t t1, int nv, const uint32_t *v)
{
    gtet_check_violation *x = &c->report->violation;
    x->tet[0] = t0;
    x->tet[1] = t1;
    x->nvertices = 0;
    for (int i = 0; i < nv && i < 5; i++) {
        if (v[i] >= c->nv) continue;  /* an out-of-range id is reported by number only */
        x->vertex[x->nvertices] = v[i];
        memcpy(x->point[x->nvertices], c->vertices + 3 * (size_t)v[i], sizeof x->point[0]);
        x->nvertices++;
    }
}

uint64_t chk_group_size(const chk_ctx *c, const uint32_t *abc, const uint32_t *abcd)
{
    const double *V = c->vertices;
    const double *p[4];
    for (int i = 0; i < (abcd ? 4 : 3); i++) p[i] = V + 3 * (size_t)(abcd ? abcd[i] : abc[i]);
    uint64_t k = 0;
    for (size_t w = 0; w < c->nv; w++) {
        if (c->unused && c->unused[w]) continue;
        const double *q = V + 3 * w;
        k += abcd ? chk_insphere(c, p[0], p[1], p[2], p[3], q) == 0
                  : chk_orient3d(c, p[0], p[1], p[2], q) == 0;
    }
    return k;
}

uint32_t chk_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];  /* path halving */
        x = parent[x];
    }
    return x;
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

/* Vertex ids in range and distinct per tet, finite vertices; returns the marks of the
 * vertices that are in some tet in *used (calloc'ed). */
static gtet_status check_ids(chk_ctx *c, uint8_t **used)
{
    const uint32_t *T = c->tets;
    const double *V = c->vertices;
    c->stage = "vertices";
    if (c->nv < 4) return chk_fail(c, "the mesh has %zu vertices; a tetrahedrization needs 4", c->nv);
    if (c->nt == 0) return chk_fail(c, "the mesh has no tets");
    for (size_t t = 0; t < c->nt; t++)
        for (int i = 0; i < 4; i++) {
            if (T[4 * t + i] >= c->nv) {
                chk_note(c, t, GTET_CHECK_NONE, 4, T + 4 * t);
                return chk_fail(c, "tet %zu has vertex id %u, out of range (%zu vertices)", t,
                                T[4 * t + i], c->nv);
            }
            for (int j = 0; j < i; j++)
                if (T[4 * t + i] == T[4 * t + j]) {
                    chk_note(c, t, GTET_CHECK_NONE, 4, T + 4 * t);
                    return chk_fail(c, "tet %zu (%u %u %u %u) repeats vertex %u", t, T[4 * t],
                                    T[4 * t + 1], T[4 * t + 2], T[4 * t + 3], T[4 * t + i]);
                }
        }
    for (size_t v = 0; v < c->nv; v++)
        if (!finite3(V + 3 * v)) {
            uint32_t id = (uint32_t)v;
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &id);
            return chk_fail(c, "vertex %zu has a non-finite coordinate", v);
        }
    if (!(*used = calloc(c->nv, 1))) return chk_oom(c);
    for (size_t t = 0; t < 4 * c->nt; t++) (*used)[T[t]] = 1;
    return GTET_OK;
}

/* keys[0..nv) sorted by point: the vertices in tets are pairwise distinct points, and a vertex
 * in no tet is accepted only as a copy of one that is in a tet (c->unused marks those).  On
 * success the keys of the used vertices are compacted to keys[0..*nk). */
static gtet_status check_distinct(chk_ctx *c, vkey *keys, const uint8_t *used, size_t *nk)
{
    const double *V = c->vertices;
    size_t k = 0;
    for (size_t g = 0; g < c->nv;) {
        size_t e = g + 1, u = SIZE_MAX;
        while (e < c->nv && orc_lex_compare(keys[g].x, keys[e].x) == 0) e++;
        for (size_t i = g; i < e; i++) {
            if (!used[keys[i].id]) continue;
            if (u != SIZE_MAX) {
                uint32_t ids[2] = {keys[u].id, keys[i].id};
                chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 2, ids);
                return chk_fail(c, "vertices %u and %u are the same point (%.17g, %.17g, %.17g)",
                                ids[0], ids[1], keys[i].x[0], keys[i].x[1], keys[i].x[2]);
            }
            u = i;
        }
        if (u == SIZE_MAX) {
            uint32_t id = keys[g].id;
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &id);
            return chk_fail(c, "vertex %u (%.17g, %.17g, %.17g) is in no tet", id, V[3 * (size_t)id],
                            V[3 * (size_t)id + 1], V[3 * (size_t)id + 2]);
        }
        if (e - g > 1) {
            if (!c->unused && !(c->unused = calloc(c->nv, 1))) return chk_oom(c);
            for (size_t i = g; i < e; i++) c->unused[keys[i].id] = i != u;
            c->report->unused_vertices += e - g - 1;
        }
        keys[k++] = keys[u];
        g = e;
    }
    *nk = k;
    if (c->unused && c->input_map)
        return chk_fail(c, "the mesh has %llu vertices in no tet (copies of other vertices)",
                        (unsigned long long)c->report->unused_vertices);
    return GTET_OK;
}

int chk_rounded_match(const void *pts, size_t stride, size_t n, const double p[3], size_t *best,
                      double *rel)
{
    size_t b = SIZE_MAX;
    double bd = INFINITY;
    for (size_t k = 0; k < n; k++) {
        const double *x = (const double *)(const void *)((const char *)pts + k * stride);
        const double d = fmax(fabs(x[0] - p[0]), fmax(fabs(x[1] - p[1]), fabs(x[2] - p[2])));
        if (d < bd) bd = d, b = k;
    }
    const double scale = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
    if (b == SIZE_MAX || !(bd <= 1e-5 * scale)) return 0;
    *best = b;
    *rel = bd / scale;
    return 1;
}

/* Input point i (p) is not a vertex.  When a vertex lies within rounding of it
 * (chk_rounded_match), the message names that vertex and says so, instead of leaving the user
 * to think a vertex is missing (NOTES.md E157). */
static gtet_status missing_input(chk_ctx *c, const vkey *keys, size_t nk, size_t i, const double *p)
{
    size_t best;
    double rel;
    if (chk_rounded_match(keys, sizeof *keys, nk, p, &best, &rel)) {
        const double *q = keys[best].x;
        return chk_fail(c, "input point %zu (%.17g, %.17g, %.17g) is not a vertex of the mesh; "
                        "vertex %u (%.17g, %.17g, %.17g) is off by a relative %.1e: were the "
                        "coordinates rounded when the mesh was written? (17 significant digits "
                        "keep them exact)", i, p[0], p[1], p[2], keys[best].id, q[0], q[1], q[2],
                        rel);
    }
    return chk_fail(c, "input point %zu (%.17g, %.17g, %.17g) is not a vertex of the mesh", i,
                    p[0], p[1], p[2]);
}

/* The used vertices (keys[0..nk), sorted) against the input points: every input point is a
 * vertex, every used vertex an input point, and with an input map the map and gigatet's
 * numbering (order of first occurrence). */
static gtet_status check_against_input(chk_ctx *c, const vkey *keys, size_t nk, uint32_t *first)
{
    const double *V = c->vertices;
    c->stage = "input";
    if (c->n >= UINT32_MAX)
        return chk_fail(c, "%zu input points: more than the checker's 32-bit indices hold", c->n);
    for (size_t v = 0; v < c->nv; v++) first[v] = UINT32_MAX;
    uint64_t dups = 0;
    for (size_t i = 0; i < c->n; i++) {
        if (chk_stop_serial(c, i)) return chk_cancelled(c);
        const double *p = c->xyz + 3 * i;
        if (!finite3(p)) return chk_fail(c, "input point %zu has a non-finite coordinate", i);
        uint32_t v = find_vertex(keys, nk, p);
        if (v == UINT32_MAX) return missing_input(c, keys, nk, i, p);
        if (c->input_map && c->input_map[i] != v) {
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &v);
            return chk_fail(c, "input_map[%zu] = %u, but input point %zu is vertex %u", i,
                            c->input_map[i], i, v);
        }
        if (first[v] == UINT32_MAX) first[v] = (uint32_t)i;
        else dups++;
    }
    c->report->duplicates = dups;
    for (size_t k = 0; k < nk; k++) {
        uint32_t v = keys[k].id;
        if (first[v] == UINT32_MAX) {
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &v);
            return chk_fail(c, "vertex %u (%.17g, %.17g, %.17g) is not an input point", v,
                            V[3 * (size_t)v], V[3 * (size_t)v + 1], V[3 * (size_t)v + 2]);
        }
    }
    /* gigatet numbers its vertices in order of first occurrence */
    for (size_t v = 1; c->input_map && v < c->nv; v++)
        if (first[v] < first[v - 1])
            return chk_fail(c, "vertex %zu first occurs at input %u, before vertex %zu (input %u): "
                            "vertices are not numbered in order of first occurrence",
                            v, first[v], v - 1, first[v - 1]);
    return GTET_OK;
}

/* Stage 1: the vertex set. */
gtet_status chk_inputs(chk_ctx *c)
{
    uint8_t *used = NULL;
    vkey *keys = NULL;
    uint32_t *first = NULL;
    size_t nk = 0;
    gtet_status st = check_ids(c, &used);
    if (st != GTET_OK) goto done;
    keys = malloc(c->nv * sizeof *keys);
    first = malloc(c->nv * sizeof *first);  /* first input index of each vertex */
    if (!keys || !first) {
        st = chk_oom(c);
        goto done;
    }
    for (size_t v = 0; v < c->nv; v++) {
        memcpy(keys[v].x, c->vertices + 3 * v, sizeof keys[v].x);
        keys[v].id = (uint32_t)v;
    }
    qsort(keys, c->nv, sizeof *keys, vkey_cmp);
    if (chk_poll(c)) {
        st = chk_cancelled(c);
        goto done;
    }
    if ((st = check_distinct(c, keys, used, &nk)) != GTET_OK) goto done;
    if (c->xyz) st = check_against_input(c, keys, nk, first);
done:
    free(used);
    free(keys);
    free(first);
    return st;
}

/* The summary of a passing check. */
static void report_ok(chk_ctx *c)
{
    gtet_check_report *r = c->report;
    char extra[160] = "";
    int k = 0;
    if (r->negative_tets)
        k += snprintf(extra + k, sizeof extra - (size_t)k, ", %llu negatively oriented tets accepted",
                      (unsigned long long)r->negative_tets);
    if (r->unused_vertices && k < (int)sizeof extra)
        k += snprintf(extra + k, sizeof extra - (size_t)k, ", %llu unused copies of vertices",
                      (unsigned long long)r->unused_vertices);
    if (c->closed && k < (int)sizeof extra)
        snprintf(extra + k, sizeof extra - (size_t)k, ", %llu co-spherical facets and %llu coplanar "
                 "hull edges (ties)", (unsigned long long)r->cospherical_facets,
                 (unsigned long long)r->coplanar_hull_edges);
    r->ok = 1;
    snprintf(r->message, sizeof r->message,
             "ok (%s): %zu vertices, %zu tets, %zu interior facets locally Delaunay%s, %zu hull "
             "facets convex, Euler characteristic %d%s%s",
             c->closed ? "Delaunay, ties allowed" : "canonical", c->nv, c->nt, c->interior_facets,
             c->closed ? " (closed sense)" : "", c->nh, r->euler,
             (c->flags & GTET_CHECK_FULL) ? ", every circumsphere empty" : "", extra);
}

gtet_status chk_run(chk_ctx *c)
{
    /* the regions' team, fixed here: OpenMP's default team would start threads the process
     * may not be allowed (libgomp then ends the process: NOTES.md E183, Q34), and a region
     * nested in a caller's gets what base_team_size says (E184) */
    int limit_error;
    c->threads = base_threads_available(base_team_size(omp_get_max_threads()), &limit_error);
    c->closed = (c->flags & GTET_CHECK_DELAUNAY) != 0;
    c->report->mode = c->closed ? (unsigned)GTET_CHECK_DELAUNAY : 0u;
    c->report->violation.tet[0] = c->report->violation.tet[1] = GTET_CHECK_NONE;
    c->level = omp_get_level();
    c->stage = "vertices";  /* a cancel names the stage running or just ended */
    /* every stage, in order; a cancel is looked for before each (and inside the long ones) */
    gtet_status (*const stage[])(chk_ctx *) = {
        chk_inputs, chk_orientation, chk_facets, chk_hull_surface, chk_euler_links,
        chk_delaunay, chk_hull_convex, chk_volume, chk_full};
    const size_t nstages = sizeof stage / sizeof stage[0] - !(c->flags & GTET_CHECK_FULL);
    gtet_status st = GTET_OK;
    for (size_t i = 0; i < nstages && st == GTET_OK; i++)
        st = chk_poll(c) ? chk_cancelled(c) : stage[i](c);
    if (st == GTET_OK && chk_poll(c)) st = chk_cancelled(c);  /* no verdict once asked */
    if (st == GTET_OK) report_ok(c);
    if (st != GTET_OK) {
        free(c->cell);
        free(c->cell_hull);
        c->cell = NULL;
        c->cell_hull = NULL;
    }
    free(c->adj);
    free(c->hull);
    free(c->hull_tf);
    free(c->hull_adj);
    free(c->own_tets);
    free(c->own_neighbors);
    free(c->unused);
    c->adj = c->hull = c->hull_tf = c->hull_adj = c->own_tets = c->own_neighbors = NULL;
    c->unused = NULL;
    return st;
}

gtet_status chk_check_arrays(const double *vertices, size_t nv, const uint32_t *tets, size_t nt,
                             const uint32_t *neighbors, const double *xyz, size_t n,
                             const gtet_check_options *opts, gtet_check_report *report,
                             uint32_t **cell, uint8_t **cell_hull)
{
    const unsigned flags = opts ? opts->flags : 0u;
    gtet_check_report local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    report->tets = nt;
    report->violation.tet[0] = report->violation.tet[1] = GTET_CHECK_NONE;
    report->mode = flags & (unsigned)GTET_CHECK_DELAUNAY;
    if ((!vertices && nv) || (!tets && nt) || (!xyz && n) || (flags & ~CHK_KNOWN_FLAGS)) {
        snprintf(report->message, sizeof report->message,
                 "invalid argument: a NULL array with a nonzero count, or unknown flags");
        report->violation.stage = "arguments";
        return GTET_ERR_ARGUMENT;
    }
    if (nv >= UINT32_MAX || nt >= UINT32_MAX / 4) {
        snprintf(report->message, sizeof report->message,
                 "%zu vertices / %zu tets: more than 32-bit ids hold", nv, nt);
        report->violation.stage = "arguments";
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
    c.cancel = opts ? opts->cancel : NULL;
    c.cancel_user = opts ? opts->cancel_user : NULL;
    c.want_cells = cell != NULL;
    gtet_status st = chk_run(&c);
    if (cell) {
        *cell = c.cell;
        *cell_hull = c.cell_hull;
    }
    return st;
}

void gtet_check_options_init(gtet_check_options *opts)
{
    if (opts) memset(opts, 0, sizeof *opts);
}

gtet_status gtet_check_arrays_opt(const double *vertices, size_t nv, const uint32_t *tets,
                                  size_t nt, const uint32_t *neighbors, const double *xyz,
                                  size_t n, const gtet_check_options *opts,
                                  gtet_check_report *report)
{
    return chk_check_arrays(vertices, nv, tets, nt, neighbors, xyz, n, opts, report, NULL, NULL);
}

gtet_status gtet_check_arrays(const double *vertices, size_t nv, const uint32_t *tets,
                              size_t nt, const uint32_t *neighbors, const double *xyz,
                              size_t n, unsigned flags, gtet_check_report *report)
{
    gtet_check_options o;
    gtet_check_options_init(&o);
    o.flags = flags;
    return chk_check_arrays(vertices, nv, tets, nt, neighbors, xyz, n, &o, report, NULL, NULL);
}
