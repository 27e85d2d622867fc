/* check_geom.c -- the geometric stages of the checker, every sign from the GMP oracle:
 * orientation, perturbed local Delaunay, the hull rule and the convexity of the hull, the
 * volume cross-check and the optional full empty-sphere test.
 *
 * Why the hull stage proves the hull convex and the tets a triangulation.  After check_topo.c
 * the hull facets form a closed surface S, oriented outward (ghost orientation), and every
 * interior facet has its two tets on opposite sides.
 *   (a) Hull rule across every hull edge: the apex x of the neighbouring hull facet does not
 *       conflict with the ghost of (a,b,c): orient3d(a,b,c,x) < 0, or x coplanar and outside
 *       the perturbed circle (gtet_ghost_conflict == -1).  So S is locally convex at every edge
 *       (weakly: flat edges are allowed and decided by the perturbation, as in CGAL).  The
 *       rule for the tet's own fourth vertex d is checked too; it holds by orientation.
 *   (b) o = the centroid of tet 0 is strictly on the inner side of every hull facet.  Then the
 *       central projection from o maps each hull facet onto a positively oriented spherical
 *       triangle, neighbours onto opposite sides of their common arc: it is a branched covering
 *       of the sphere by S, of some degree d >= 1 (>= 1 per component of S).
 *   (c) The ray from o through the centroid X of hull facet 0 lies in the closed cone of
 *       exactly one hull facet.  X is not the image of a vertex, so the count is d: d = 1, S is
 *       connected, embedded and star-shaped around o; an embedded closed surface locally convex
 *       at every edge is locally convex at its vertices too (a simple spherical polygon turning
 *       one way is convex), hence it bounds a convex body K (Tietze-Nakajima).
 * The number of tets containing a generic point changes only across hull facets (by one, the
 * tets lie inside), so it is the winding number of S: 1 in K, 0 outside.  The tets tile K, and
 * K = conv(vertices) since every vertex is in a tet.  With (every interior facet) perturbed
 * local Delaunay, the Delaunay lemma (see check.c) finishes the proof.
 *
 * The volume comparison (sum of the tets' 6*volume = the volume S encloses, by the divergence
 * theorem) is an independent cross-check of the facet bookkeeping; it follows from the stages
 * above and is kept because it is cheap and catches errors in them.
 * Orientation, insphere and hull-rule signs come from check_filter.c (interval arithmetic, then
 * the oracle); the centroid tests and the volume from the oracle directly.
 * The loops over tets run in parallel (OpenMP); each reports its smallest failing index, so the
 * message is the same for any thread count.
 */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "../oracle/oracle.h"
#include "check_internal.h"

#define P(v) (c->vertices + 3 * (size_t)(v))

/* With GTET_CHECK_ANY_ORIENTATION, the tets (and neighbors) are copied with every negative
 * tet's vertices 0 and 1 swapped (its neighbors 0 and 1 with them), so the later stages see
 * positive tets only; tet ids do not change. */
static gtet_status turn_positive(chk_ctx *c, const uint8_t *neg)
{
    c->own_tets = malloc(4 * c->nt * sizeof *c->own_tets);
    if (c->neighbors) c->own_neighbors = malloc(4 * c->nt * sizeof *c->own_neighbors);
    if (!c->own_tets || (c->neighbors && !c->own_neighbors)) return chk_oom(c);
    memcpy(c->own_tets, c->tets, 4 * c->nt * sizeof *c->own_tets);
    if (c->neighbors) memcpy(c->own_neighbors, c->neighbors, 4 * c->nt * sizeof *c->own_neighbors);
    for (size_t t = 0; t < c->nt; t++) {
        if (!neg[t]) continue;
        uint32_t x = c->own_tets[4 * t];
        c->own_tets[4 * t] = c->own_tets[4 * t + 1];
        c->own_tets[4 * t + 1] = x;
        if (!c->neighbors) continue;
        x = c->own_neighbors[4 * t];
        c->own_neighbors[4 * t] = c->own_neighbors[4 * t + 1];
        c->own_neighbors[4 * t + 1] = x;
    }
    c->tets = c->own_tets;
    if (c->neighbors) c->neighbors = c->own_neighbors;
    return GTET_OK;
}

gtet_status chk_orientation(chk_ctx *c)
{
    const uint32_t *T = c->tets;
    int any = (c->flags & GTET_CHECK_ANY_ORIENTATION) != 0;
    uint8_t *neg = any ? calloc(c->nt, 1) : NULL;
    if (any && !neg) return chk_oom(c);
    c->stage = "orientation";
    size_t bad = SIZE_MAX;
    uint64_t nneg = 0;
#pragma omp parallel for num_threads(c->threads) reduction(min : bad) reduction(+ : nneg) \
    schedule(dynamic, 512) if (c->nt > 8192)
    for (size_t t = 0; t < c->nt; t++) {
        if (chk_stop(c, t)) continue;
        const uint32_t *v = T + 4 * t;
        int o = chk_orient3d(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]));
        if (o < 0 && any) {
            neg[t] = 1;
            nneg++;
        } else if (o <= 0 && t < bad) {
            bad = t;
        }
    }
    gtet_status st = GTET_OK;
    if (chk_is_cancelled(c)) {  /* a skipped tet may hide the first violation */
        st = chk_cancelled(c);
    } else if (bad != SIZE_MAX) {
        const uint32_t *v = T + 4 * bad;
        int o = chk_orient3d(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]));
        chk_note(c, bad, GTET_CHECK_NONE, 4, v);
        st = chk_fail(c, "tet %zu (%u %u %u %u) is %s (orient3d = %d)%s", bad, v[0], v[1], v[2],
                      v[3], o < 0 ? "negatively oriented" : "flat", o,
                      o < 0 ? "; --any-orientation accepts negatively oriented tets" : "");
    } else {
        c->report->negative_tets = nneg;
        if (nneg) st = turn_positive(c, neg);
    }
    free(neg);
    return st;
}

/* The vertex of tet u that is not a vertex of tet t (they share a facet). */
static uint32_t apex_across(const uint32_t *T, size_t t, uint32_t u)
{
    for (int j = 0; j < 4; j++) {
        uint32_t w = T[4 * (size_t)u + j];
        if (w != T[4 * t] && w != T[4 * t + 1] && w != T[4 * t + 2] && w != T[4 * t + 3]) return w;
    }
    return UINT32_MAX;  /* not reached after chk_facets */
}

/* Mark the violation about to be reported as a tie, with the size of its group (see
 * chk_group_size). */
static const gtet_check_violation *note_tie(chk_ctx *c, const uint32_t *abc, const uint32_t *abcd)
{
    gtet_check_violation *x = &c->report->violation;
    x->tie = 1;
    x->group_size = chk_group_size(c, abc, abcd);
    return x;
}

/* The sign that decides facet f of tet t against the apex e across it: the perturbed insphere
 * (canonical mode: -1 is locally Delaunay) or the plain one (closed mode: <= 0 is). */
static int facet_sign(const chk_ctx *c, const uint32_t *v, uint32_t e)
{
    if (c->closed) return chk_insphere(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(e));
    return chk_insphere_sos(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(e));
}

/* Join the tets across the facets marked co-spherical: the classes are the Delaunay cells. */
static gtet_status join_cells(chk_ctx *c, const uint8_t *tie)
{
    for (size_t t = 0; t < c->nt; t++) c->cell[t] = (uint32_t)t;
    for (size_t tf = 0; tf < 4 * c->nt; tf++) {
        if (c->adj[tf] == GTET_NO_TET) c->cell_hull[tf / 4] = 1;
        if (!tie[tf]) continue;
        uint32_t r1 = chk_find(c->cell, (uint32_t)(tf / 4)), r2 = chk_find(c->cell, c->adj[tf]);
        if (r1 != r2) c->cell[r1 > r2 ? r1 : r2] = r1 > r2 ? r2 : r1;
    }
    return GTET_OK;
}

gtet_status chk_delaunay(chk_ctx *c)
{
    const uint32_t *T = c->tets;
    size_t bad = SIZE_MAX;
    uint64_t ties = 0;
    uint8_t *tie = NULL;
    c->stage = "delaunay";
    if (c->want_cells && c->closed) {
        tie = calloc(4 * c->nt, 1);
        c->cell = malloc(c->nt * sizeof *c->cell);
        c->cell_hull = calloc(c->nt, 1);
        if (!tie || !c->cell || !c->cell_hull) {
            free(tie);
            return chk_oom(c);
        }
    }
#pragma omp parallel for num_threads(c->threads) reduction(min : bad) reduction(+ : ties) \
    schedule(dynamic, 512) if (c->nt > 8192)
    for (size_t t = 0; t < c->nt; t++) {
        if (chk_stop(c, t)) continue;
        const uint32_t *v = T + 4 * t;
        for (int f = 0; f < 4; f++) {
            uint32_t u = c->adj[4 * t + f];
            if (u == GTET_NO_TET || u < t) continue;  /* each interior facet once */
            int sg = facet_sign(c, v, apex_across(T, t, u));
            if (c->closed && sg == 0) {
                ties++;
                if (tie) tie[4 * t + (size_t)f] = 1;
            }
            if (sg > 0 || (!c->closed && sg == 0)) {
                if (4 * t + f < bad) bad = 4 * t + (size_t)f;
            }
        }
    }
    if (chk_is_cancelled(c)) {
        free(tie);
        return chk_cancelled(c);
    }
    c->report->facets_checked = c->interior_facets;
    c->report->cospherical_facets = ties;
    if (bad == SIZE_MAX) {
        if (tie) join_cells(c, tie);
        free(tie);
        return GTET_OK;
    }
    free(tie);
    size_t t = bad / 4;
    int f = (int)(bad % 4);
    const uint32_t *v = T + 4 * t;
    uint32_t u = c->adj[bad], e = apex_across(T, t, u);
    uint32_t o[3], five[5] = {v[0], v[1], v[2], v[3], e};
    chk_outward_facet(v, f, o);
    chk_note(c, t, u, 5, five);
    if (!c->closed && chk_insphere(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(e)) == 0) {
        const gtet_check_violation *x = note_tie(c, NULL, v);
        return chk_fail(c, "facet (%u %u %u) between tets %zu and %u is not locally Delaunay in "
                        "the canonical sense, a tie broken against the symbolic perturbation: "
                        "vertex %u of tet %u is exactly on the circumsphere of tet %zu (%u %u %u "
                        "%u), a co-spherical group of %llu vertices (one is (%.17g, %.17g, "
                        "%.17g)), and the perturbation puts it inside (--delaunay accepts ties)",
                        o[0], o[1], o[2], t, u, e, u, t, v[0], v[1], v[2], v[3],
                        (unsigned long long)x->group_size, P(e)[0], P(e)[1], P(e)[2]);
    }
    return chk_fail(c, "facet (%u %u %u) between tets %zu and %u is not locally Delaunay: vertex "
                    "%u of tet %u is inside the %scircumsphere of tet %zu (%u %u %u %u)",
                    o[0], o[1], o[2], t, u, e, u, c->closed ? "" : "perturbed ", t, v[0], v[1],
                    v[2], v[3]);
}

gtet_status chk_hull_convex(chk_ctx *c)
{
    const uint32_t *T = c->tets, *H = c->hull;
    /* (a) the hull rule on the ghost's four neighbours: the tet's own apex, then across the
     * three hull edges the apex of the neighbouring hull facet.  In closed mode the plain
     * orientation: not beyond the facet's plane (coplanar allowed: weak convexity). */
    c->stage = "hull";
    uint64_t flat = 0;
    for (size_t h = 0; h < c->nh; h++) {
        const uint32_t *a = H + 3 * h;
        uint32_t d = T[c->hull_tf[h]];
        int sd = c->closed ? chk_orient3d(c, P(a[0]), P(a[1]), P(a[2]), P(d))
                           : chk_ghost_conflict(c, P(a[0]), P(a[1]), P(a[2]), P(d));
        if (sd != -1) {
            chk_note(c, c->hull_tf[h] / 4, GTET_CHECK_NONE, 4, T + 4 * (size_t)(c->hull_tf[h] / 4));
            return chk_fail(c, "hull facet (%u %u %u) faces into its own tet %u: vertex %u "
                            "conflicts with its ghost", a[0], a[1], a[2], c->hull_tf[h] / 4, d);
        }
        for (int i = 0; i < 3; i++) {
            size_t hb = c->hull_adj[3 * h + i];
            const uint32_t *b = H + 3 * hb;
            uint32_t x = UINT32_MAX;
            for (int j = 0; j < 3; j++)
                if (b[j] != a[i] && b[j] != a[(i + 1) % 3]) x = b[j];
            int sx = c->closed ? chk_orient3d(c, P(a[0]), P(a[1]), P(a[2]), P(x))
                               : chk_ghost_conflict(c, P(a[0]), P(a[1]), P(a[2]), P(x));
            flat += c->closed && sx == 0;
            if (sx == 1 || (!c->closed && sx != -1)) {
                uint32_t four[4] = {a[0], a[1], a[2], x};
                chk_note(c, c->hull_tf[h] / 4, c->hull_tf[hb] / 4, 4, four);
                if (!c->closed && chk_orient3d(c, P(a[0]), P(a[1]), P(a[2]), P(x)) == 0) {
                    const gtet_check_violation *v = note_tie(c, a, NULL);
                    return chk_fail(c, "the hull is not convex in the canonical sense at edge "
                                    "(%u %u), a tie broken against the symbolic perturbation: "
                                    "hull facets (%u %u %u) and (%u %u %u) are coplanar, in a "
                                    "coplanar hull group of %llu vertices (one is (%.17g, %.17g, "
                                    "%.17g)), and the perturbed circle puts vertex %u inside the "
                                    "first's (--delaunay accepts ties)", a[i], a[(i + 1) % 3],
                                    a[0], a[1], a[2], b[0], b[1], b[2],
                                    (unsigned long long)v->group_size, P(x)[0], P(x)[1], P(x)[2], x);
                }
                return chk_fail(c, "the hull is not convex at edge (%u %u): vertex %u of hull facet "
                                "(%u %u %u) %s hull facet (%u %u %u)", a[i], a[(i + 1) % 3], x,
                                b[0], b[1], b[2],
                                c->closed ? "is beyond the plane of" : "conflicts with the ghost of",
                                a[0], a[1], a[2]);
            }
        }
    }
    c->report->coplanar_hull_edges = flat / 2;  /* each edge is seen from both of its facets */
    /* (b) the centroid o of tet 0 strictly inside every hull facet */
    const double *pts[9];
    for (int i = 0; i < 4; i++) pts[i] = P(T[i]);
    for (size_t h = 0; h < c->nh; h++) {
        const uint32_t *a = H + 3 * h;
        const double *q[7] = {P(a[0]), P(a[1]), P(a[2]), pts[0], pts[1], pts[2], pts[3]};
        static const int cnt[4] = {1, 1, 1, 4};
        if (orc_orient3d_avg(q, cnt) >= 0) {
            chk_note(c, c->hull_tf[h] / 4, GTET_CHECK_NONE, 3, a);
            return chk_fail(c, "the centroid of tet 0 is not strictly inside hull facet (%u %u %u): "
                            "the hull is not convex", a[0], a[1], a[2]);
        }
    }
    /* (c) the ray from o through the centroid of hull facet 0 meets exactly one hull facet */
    for (int i = 0; i < 3; i++) pts[6 + i] = P(H[i]);
    size_t hits = 0;
    for (size_t h = 0; h < c->nh; h++) {
        const uint32_t *a = H + 3 * h;
        int inside = 1;
        for (int i = 0; i < 3 && inside; i++) {
            pts[4] = P(a[i]);
            pts[5] = P(a[(i + 1) % 3]);
            static const int cnt[4] = {4, 1, 1, 3};  /* (o, p, q, X) */
            inside = orc_orient3d_avg(pts, cnt) >= 0;
        }
        hits += (size_t)inside;
    }
    if (hits != 1)
        return chk_fail(c, "a ray from the centroid of tet 0 meets %zu hull facets, not 1: the hull "
                        "wraps around it %s", hits, hits ? "more than once" : "zero times");
    c->report->facets_checked += c->nh;
    return GTET_OK;
}

/* The oracle's stop hook: chk_stop on the tets' sum (the calling thread is thread 0 of the
 * oracle's region, started from here). */
static int volume_stop(void *c, size_t i) { return chk_stop(c, i); }

gtet_status chk_volume(chk_ctx *c)
{
    c->stage = "volume";
    int s = orc_compare_volume(c->vertices, c->nv, c->tets, c->nt, c->hull, c->nh, c->threads,
                               c->cancel ? volume_stop : NULL, c);
    if (chk_is_cancelled(c)) return chk_cancelled(c);
    if (s == 0) return GTET_OK;
    return chk_fail(c, "the tets' total volume is %s the volume the hull encloses",
                    s > 0 ? "larger than" : "smaller than");
}

/* In the full test a point w violates tet v when it is strictly inside its circumsphere
 * (closed mode) or inside its perturbed circumsphere (canonical mode). */
static int full_violates(const chk_ctx *c, const uint32_t *v, size_t w)
{
    if (c->closed) return chk_insphere(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(w)) > 0;
    return chk_insphere_sos(c, P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(w)) != -1;
}

gtet_status chk_full(chk_ctx *c)
{
    const uint32_t *T = c->tets, *H = c->hull;
    size_t nv = c->nv, bad = SIZE_MAX;
    c->stage = "full";
#pragma omp parallel for num_threads(c->threads) reduction(min : bad) schedule(dynamic, 16) \
    if (c->nt * c->nv > 1000000)
    for (size_t t = 0; t < c->nt; t++) {
        if (chk_is_cancelled(c)) continue;
        const uint32_t *v = T + 4 * t;
        for (size_t w = 0; w < nv; w++) {
            if (chk_stop(c, w)) break;
            if (w == v[0] || w == v[1] || w == v[2] || w == v[3]) continue;
            if (c->unused && c->unused[w]) continue;
            if (full_violates(c, v, w)) {
                if (t * nv + w < bad) bad = t * nv + w;
                break;
            }
        }
    }
    if (chk_is_cancelled(c)) return chk_cancelled(c);
    if (bad != SIZE_MAX) {
        size_t t = bad / nv, w = bad % nv;
        const uint32_t *v = T + 4 * t;
        uint32_t five[5] = {v[0], v[1], v[2], v[3], (uint32_t)w};
        chk_note(c, t, GTET_CHECK_NONE, 5, five);
        return chk_fail(c, "vertex %zu is inside the %scircumsphere of tet %zu (%u %u %u %u)", w,
                        c->closed ? "" : "perturbed ", t, v[0], v[1], v[2], v[3]);
    }
    for (size_t h = 0; h < c->nh; h++) {
        const uint32_t *a = H + 3 * h;
        for (size_t w = 0; w < nv; w++) {
            if (chk_stop(c, w)) return chk_cancelled(c);
            if (w == a[0] || w == a[1] || w == a[2]) continue;
            if (c->unused && c->unused[w]) continue;
            int s = c->closed ? chk_orient3d(c, P(a[0]), P(a[1]), P(a[2]), P(w))
                              : chk_ghost_conflict(c, P(a[0]), P(a[1]), P(a[2]), P(w));
            if (s == 1 || (!c->closed && s != -1)) {
                uint32_t four[4] = {a[0], a[1], a[2], (uint32_t)w};
                chk_note(c, c->hull_tf[h] / 4, GTET_CHECK_NONE, 4, four);
                return chk_fail(c, "vertex %zu conflicts with the ghost of hull facet (%u %u %u): "
                                "it is beyond the hull", w, a[0], a[1], a[2]);
            }
        }
    }
    return GTET_OK;
}
