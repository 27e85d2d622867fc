/* diff.c -- gtet_diff(): two meshes of one point set compared as sets of tets over coordinates,
 * and, when they differ, why.
 *
 * Matching.  Every vertex of A and of B gets a common id: the rank of its point among the
 * distinct points of both meshes in lexicographic (x, y, z) order (exact comparisons of the
 * doubles, -0.0 == +0.0).  A tet is then the sorted 4-tuple of its common ids, so vertex
 * numbering, the order of a tet's vertices and its orientation do not matter.  Sorting the
 * tuples of each mesh and merging them counts the tets in both and in one only.
 *
 * Verdict.  Equal tuple multisets over equal point sets: identical.  Different point sets:
 * POINTS.  Otherwise each mesh goes through the exact checker in closed Delaunay mode with any
 * orientation (src/check/check.c).  When both pass, both are Delaunay tetrahedrizations of one
 * point set, and such tetrahedrizations differ only inside the cells of the Delaunay
 * subdivision that are not tets: each such cell is the convex hull of >= 5 co-spherical points
 * (its empty sphere), and every Delaunay tetrahedrization triangulates each cell with tets of
 * its own vertices.  The checker joins the tets across interior facets whose five vertices are
 * co-spherical; a class of that relation is exactly one cell's triangulation (two tets of one
 * cell are linked through the cell's facet-connected triangulation, and a facet between two
 * cells has an apex strictly outside the other tet's sphere).  A group is a cell holding a tet
 * of one mesh only; its vertex set is the same in A and B, so the groups of the two meshes are
 * matched by their sorted vertex lists.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../oracle/oracle.h"
#include "check_internal.h"

typedef struct pkey {
    const double *x;
    uint32_t id;    /* vertex id in its mesh */
    uint8_t side;   /* 0 = A, 1 = B */
} pkey;

static int pkey_cmp(const void *pa, const void *pb)
{
    const pkey *a = pa, *b = pb;
    int s = orc_lex_compare(a->x, b->x);
    if (s) return s;
    if (a->side != b->side) return a->side < b->side ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

typedef struct tkey {
    uint32_t v[4];  /* sorted common ids */
    uint32_t t;     /* tet index in its mesh */
} tkey;

static int tkey_cmp_v(const tkey *a, const tkey *b)
{
    for (int i = 0; i < 4; i++)
        if (a->v[i] != b->v[i]) return a->v[i] < b->v[i] ? -1 : 1;
    return 0;
}

static int tkey_cmp(const void *pa, const void *pb)
{
    const tkey *a = pa, *b = pb;
    int s = tkey_cmp_v(a, b);
    return s ? s : (a->t > b->t) - (a->t < b->t);
}

typedef struct side {
    const double *v;
    size_t nv;
    const uint32_t *t;
    size_t nt;
    uint32_t *gid;      /* nv: common id of each vertex */
    tkey *keys;         /* nt, sorted */
    uint8_t *only;      /* nt: 1 for a tet that is not in the other mesh */
    uint32_t *cell;     /* nt: Delaunay cell classes (from the checker) */
    uint8_t *cell_hull;
    gtet_check_report *check;
} side;

static int ids_in_range(const side *s)
{
    for (size_t i = 0; i < 4 * s->nt; i++)
        if (s->t[i] >= s->nv) return 0;
    return 1;
}

/* Common ids for both vertex sets; counts of distinct points in one mesh only, the first of
 * them in r->first_point_only and its mesh in *first_side (0 = A, 1 = B). */
static gtet_status common_ids(side *a, side *b, gtet_diff_report *r, int *first_side)
{
    size_t n = a->nv + b->nv;
    pkey *k = malloc((n ? n : 1) * sizeof *k);
    if (!k) return GTET_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < a->nv; i++) k[i] = (pkey){a->v + 3 * i, (uint32_t)i, 0};
    for (size_t i = 0; i < b->nv; i++) k[a->nv + i] = (pkey){b->v + 3 * i, (uint32_t)i, 1};
    qsort(k, n, sizeof *k, pkey_cmp);
    uint32_t id = 0;
    for (size_t g = 0; g < n; id++) {
        size_t e = g;
        int in[2] = {0, 0};
        while (e < n && orc_lex_compare(k[g].x, k[e].x) == 0) {
            in[k[e].side] = 1;
            (k[e].side ? b : a)->gid[k[e].id] = id;
            e++;
        }
        if (in[0] != in[1]) {
            if (!r->points_only_a && !r->points_only_b) {
                memcpy(r->first_point_only, k[g].x, 24);
                *first_side = in[1];
            }
            r->points_only_a += in[0];
            r->points_only_b += in[1];
        }
        g = e;
    }
    free(k);
    return GTET_OK;
}

/* The point of the other mesh within rounding (chk_rounded_match) of the first point in one
 * mesh only: the meshes' writers most likely rounded the coordinates differently, and the
 * verdict says so, as the checker's message does for an input point (NOTES.md E157, E181). */
typedef struct near_point {
    int side;      /* the mesh of r->first_point_only: 0 = A, 1 = B */
    int found;     /* q, a point of the other mesh, is within the bound */
    double q[3];
    double rel;    /* its distance relative to the point's largest coordinate */
} near_point;

static void nearest_other(const side *other, const double p[3], near_point *np)
{
    size_t best;
    np->found = chk_rounded_match(other->v, 3 * sizeof *other->v, other->nv, p, &best, &np->rel);
    if (np->found) memcpy(np->q, other->v + 3 * best, sizeof np->q);
}

static void sort4(uint32_t v[4])
{
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
            uint32_t x = v[j];
            v[j] = v[j - 1];
            v[j - 1] = x;
        }
}

static void tet_keys(side *s)
{
    for (size_t t = 0; t < s->nt; t++) {
        for (int i = 0; i < 4; i++) s->keys[t].v[i] = s->gid[s->t[4 * t + i]];
        sort4(s->keys[t].v);
        s->keys[t].t = (uint32_t)t;
    }
    qsort(s->keys, s->nt, sizeof *s->keys, tkey_cmp);
}

/* Merge the sorted keys: mark the tets of one mesh only, count the common ones. */
static void merge(side *a, side *b, gtet_diff_report *r)
{
    size_t i = 0, j = 0;
    while (i < a->nt || j < b->nt) {
        int c = i == a->nt ? 1 : j == b->nt ? -1 : tkey_cmp_v(&a->keys[i], &b->keys[j]);
        if (c == 0) {
            r->common++;
            i++;
            j++;
        } else if (c < 0) {
            a->only[a->keys[i++].t] = 1;
            r->only_a++;
        } else {
            b->only[b->keys[j++].t] = 1;
            r->only_b++;
        }
    }
}

/* The groups of one side: for every cell holding a tet of this side only, its sorted vertex
 * list (common ids).  list[off[g] .. off[g+1]) for g < *ng; counts of tets per group. */
typedef struct glist {
    size_t ng;
    size_t *off;
    uint32_t *ids;
    uint64_t *tets, *only;
    uint8_t *hull;
    uint32_t *first_tet;  /* a tet of the group (for its sphere) */
} glist;

typedef struct rv {
    uint32_t root, id;
} rv;

static int rv_cmp(const void *pa, const void *pb)
{
    const rv *a = pa, *b = pb;
    if (a->root != b->root) return a->root < b->root ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

static void glist_free(glist *g)
{
    free(g->off);
    free(g->ids);
    free(g->tets);
    free(g->only);
    free(g->hull);
    free(g->first_tet);
    memset(g, 0, sizeof *g);
}

static gtet_status side_groups(side *s, glist *g)
{
    memset(g, 0, sizeof *g);
    uint8_t *marked = calloc(s->nt ? s->nt : 1, 1);
    if (!marked) return GTET_ERR_OUT_OF_MEMORY;
    size_t m = 0;
    for (size_t t = 0; t < s->nt; t++)
        if (s->only[t]) marked[chk_find(s->cell, (uint32_t)t)] = 1;
    for (size_t t = 0; t < s->nt; t++) m += marked[chk_find(s->cell, (uint32_t)t)];
    rv *e = malloc((m ? 4 * m : 1) * sizeof *e);
    gtet_status st = GTET_ERR_OUT_OF_MEMORY;
    if (!e) goto out;
    size_t k = 0;
    for (size_t t = 0; t < s->nt; t++) {
        uint32_t r = chk_find(s->cell, (uint32_t)t);
        if (!marked[r]) continue;
        for (int i = 0; i < 4; i++) e[k++] = (rv){r, s->gid[s->t[4 * t + i]]};
    }
    qsort(e, k, sizeof *e, rv_cmp);
    size_t ng = 0, nid = 0;
    for (size_t i = 0; i < k; i++) {
        ng += i == 0 || e[i].root != e[i - 1].root;
        nid += i == 0 || e[i].root != e[i - 1].root || e[i].id != e[i - 1].id;
    }
    g->off = malloc((ng + 1) * sizeof *g->off);
    g->ids = malloc((nid ? nid : 1) * sizeof *g->ids);
    g->tets = calloc(ng ? ng : 1, sizeof *g->tets);
    g->only = calloc(ng ? ng : 1, sizeof *g->only);
    g->hull = calloc(ng ? ng : 1, 1);
    g->first_tet = malloc((ng ? ng : 1) * sizeof *g->first_tet);
    uint32_t *gi = malloc(s->nt * sizeof *gi + 1);  /* root -> group index */
    if (!g->off || !g->ids || !g->tets || !g->only || !g->hull || !g->first_tet || !gi) {
        free(gi);
        glist_free(g);
        goto out;
    }
    g->ng = ng;
    size_t gg = SIZE_MAX, q = 0;
    for (size_t i = 0; i < k; i++) {
        if (i == 0 || e[i].root != e[i - 1].root) {
            g->off[++gg] = q;
            gi[e[i].root] = (uint32_t)gg;
            g->first_tet[gg] = e[i].root;
        }
        if (i == 0 || e[i].root != e[i - 1].root || e[i].id != e[i - 1].id) g->ids[q++] = e[i].id;
    }
    g->off[ng] = q;
    for (size_t t = 0; t < s->nt; t++) {
        uint32_t r = chk_find(s->cell, (uint32_t)t);
        if (!marked[r]) continue;
        g->tets[gi[r]]++;
        g->only[gi[r]] += s->only[t];
        g->hull[gi[r]] |= s->cell_hull[t];
    }
    free(gi);
    st = GTET_OK;
out:
    free(e);
    free(marked);
    return st;
}

/* Compare group ga of A with group gb of B by vertex list. */
static int group_cmp(const glist *A, size_t ga, const glist *B, size_t gb)
{
    size_t na = A->off[ga + 1] - A->off[ga], nb = B->off[gb + 1] - B->off[gb];
    for (size_t i = 0; i < na && i < nb; i++) {
        uint32_t x = A->ids[A->off[ga] + i], y = B->ids[B->off[gb] + i];
        if (x != y) return x < y ? -1 : 1;
    }
    return (na > nb) - (na < nb);
}

typedef struct gref {
    const glist *l;
    size_t g;
} gref;

static int gref_cmp(const void *pa, const void *pb)
{
    const gref *a = pa, *b = pb;
    return group_cmp(a->l, a->g, b->l, b->g);
}

/* A point of the group (its smallest common id's point: the common ids are ranks in
 * lexicographic order; vof maps a common id to a vertex of this side) and the circumcentre of
 * one of its tets. */
static void group_geometry(const side *s, const uint32_t *vof, const glist *l, size_t g,
                           gtet_diff_group *out)
{
    memcpy(out->point, s->v + 3 * (size_t)vof[l->ids[l->off[g]]], sizeof out->point);
    const uint32_t *t = s->t + 4 * (size_t)l->first_tet[g];
    const double *p0 = s->v + 3 * (size_t)t[0];
    double m[3][3], rhs[3];
    for (int i = 0; i < 3; i++) {
        const double *p = s->v + 3 * (size_t)t[i + 1];
        rhs[i] = 0;
        for (int j = 0; j < 3; j++) {
            m[i][j] = p[j] - p0[j];
            rhs[i] += 0.5 * m[i][j] * m[i][j];
        }
    }
    /* Cramer's rule in doubles: the centre is for orientation only */
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int j = 0; j < 3; j++) {
        double mm[3][3];
        memcpy(mm, m, sizeof mm);
        for (int i = 0; i < 3; i++) mm[i][j] = rhs[i];
        double dj = mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) -
                    mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0]) +
                    mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0]);
        out->center[j] = p0[j] + dj / det;
    }
}

/* Match the groups of A and B by vertex list into r->groups (sorted by vertex list, which is
 * the order of their smallest points). */
static gtet_status match_groups(side *a, side *b, gtet_diff_report *r)
{
    glist ga, gb;
    gtet_status st = side_groups(a, &ga);
    if (st != GTET_OK) return st;
    if ((st = side_groups(b, &gb)) != GTET_OK) {
        glist_free(&ga);
        return st;
    }
    size_t n = ga.ng + gb.ng;
    uint32_t *vof[2] = {NULL, NULL};
    gref *all = malloc((n ? n : 1) * sizeof *all);
    r->groups = calloc(n ? n : 1, sizeof *r->groups);
    if (!all || !r->groups) {
        st = GTET_ERR_OUT_OF_MEMORY;
        goto out;
    }
    /* common id -> a vertex of each side (both sides have every common id: same point sets) */
    size_t nid = 0;
    for (size_t v = 0; v < a->nv; v++)
        if (a->gid[v] + (size_t)1 > nid) nid = a->gid[v] + (size_t)1;
    vof[0] = malloc((nid ? nid : 1) * sizeof *vof[0]);
    vof[1] = malloc((nid ? nid : 1) * sizeof *vof[1]);
    if (!vof[0] || !vof[1]) {
        st = GTET_ERR_OUT_OF_MEMORY;
        goto out;
    }
    for (size_t v = 0; v < a->nv; v++) vof[0][a->gid[v]] = (uint32_t)v;
    for (size_t v = 0; v < b->nv; v++)
        if (b->gid[v] < nid) vof[1][b->gid[v]] = (uint32_t)v;
    for (size_t i = 0; i < ga.ng; i++) all[i] = (gref){&ga, i};
    for (size_t i = 0; i < gb.ng; i++) all[ga.ng + i] = (gref){&gb, i};
    qsort(all, n, sizeof *all, gref_cmp);
    size_t ng = 0;
    for (size_t i = 0; i < n;) {
        size_t e = i + 1;
        while (e < n && gref_cmp(&all[i], &all[e]) == 0) e++;
        gtet_diff_group *out = &r->groups[ng++];
        for (size_t k = i; k < e; k++) {
            const glist *l = all[k].l;
            size_t g = all[k].g;
            out->size = l->off[g + 1] - l->off[g];
            out->on_hull |= l->hull[g];
            if (l == &ga) {
                out->tets_a += l->tets[g];
                out->only_a += l->only[g];
            } else {
                out->tets_b += l->tets[g];
                out->only_b += l->only[g];
            }
            if (k == i) group_geometry(l == &ga ? a : b, vof[l == &ga ? 0 : 1], l, g, out);
        }
        i = e;
    }
    r->num_groups = ng;
out:
    free(vof[0]);
    free(vof[1]);
    free(all);
    glist_free(&ga);
    glist_free(&gb);
    return st;
}

static gtet_status check_side(side *s, const double *xyz, size_t n)
{
    s->check->tets = s->nt;
    gtet_check_options o;
    gtet_check_options_init(&o);
    o.flags = GTET_CHECK_DELAUNAY | GTET_CHECK_ANY_ORIENTATION;
    return chk_check_arrays(s->v, s->nv, s->t, s->nt, NULL, xyz, n, &o, s->check, &s->cell,
                            &s->cell_hull);
}

/* Identical meshes with input points: the promise "against xyz when given" holds for them too,
 * and one check judges both (the same tets over the same points).  A failure -- a point of xyz
 * that is no vertex, a vertex that is no point of xyz, or the mesh not Delaunay -- makes the
 * verdict NEITHER_DELAUNAY with the check's message on both sides: an identical pair that is
 * not a triangulation of the input must not pass (NOTES.md Q33). */
static gtet_status identical_against_input(side *a, const double *xyz, size_t n,
                                           gtet_diff_report *r)
{
    gtet_status st = check_side(a, xyz, n);
    if (st == GTET_ERR_OUT_OF_MEMORY) return st;
    if (st != GTET_OK) {
        r->check_b = r->check_a;
        r->kind = GTET_DIFF_NEITHER_DELAUNAY;
    }
    return GTET_OK;
}

static void verdict(gtet_diff_report *r, const near_point *np)
{
    char *m = r->message;
    size_t z = sizeof r->message;
    switch (r->kind) {
    case GTET_DIFF_IDENTICAL:
        snprintf(m, z, "identical: the same %llu tets over the same points",
                 (unsigned long long)r->common);
        break;
    case GTET_DIFF_POINTS: {
        const char *mine = np->side ? "B" : "A", *other = np->side ? "A" : "B";
        int at = snprintf(m, z, "different point sets: %llu points only in A, %llu only in B (one "
                          "is %s's (%.17g, %.17g, %.17g))", (unsigned long long)r->points_only_a,
                          (unsigned long long)r->points_only_b, mine, r->first_point_only[0],
                          r->first_point_only[1], r->first_point_only[2]);
        if (np->found && at > 0 && (size_t)at < z)
            snprintf(m + at, z - (size_t)at, "; %s's nearest point (%.17g, %.17g, %.17g) is off by "
                     "a relative %.1e: were the coordinates rounded when a mesh was written? (17 "
                     "significant digits keep them exact)", other, np->q[0], np->q[1], np->q[2],
                     np->rel);
        break;
    }
    case GTET_DIFF_TIES:
        snprintf(m, z, "both Delaunay, different tie-breaking: %llu tets only in A, %llu only in "
                 "B, in %llu co-spherical groups", (unsigned long long)r->only_a,
                 (unsigned long long)r->only_b, (unsigned long long)r->num_groups);
        break;
    case GTET_DIFF_A_NOT_DELAUNAY:
        snprintf(m, z, "A is not Delaunay: %.480s", r->check_a.message);
        break;
    case GTET_DIFF_B_NOT_DELAUNAY:
        snprintf(m, z, "B is not Delaunay: %.480s", r->check_b.message);
        break;
    case GTET_DIFF_NEITHER_DELAUNAY:
        if (r->common && !r->only_a && !r->only_b)  /* identical_against_input's verdict */
            snprintf(m, z, "identical, and neither is a Delaunay mesh of the input points: %.440s",
                     r->check_a.message);
        else
            snprintf(m, z, "neither is Delaunay; A: %.480s", r->check_a.message);
        break;
    }
}

void gtet_diff_report_free(gtet_diff_report *r)
{
    if (!r) return;
    free(r->groups);
    r->groups = NULL;
    r->num_groups = 0;
}

static gtet_status diff_run(side *a, side *b, const double *xyz, size_t n, gtet_diff_report *r,
                            near_point *np)
{
    gtet_status st = GTET_OK;
    int valid_ids = ids_in_range(a) && ids_in_range(b);
    if (valid_ids) {
        a->gid = malloc((a->nv ? a->nv : 1) * sizeof *a->gid);
        b->gid = malloc((b->nv ? b->nv : 1) * sizeof *b->gid);
        a->keys = malloc((a->nt ? a->nt : 1) * sizeof *a->keys);
        b->keys = malloc((b->nt ? b->nt : 1) * sizeof *b->keys);
        a->only = calloc(a->nt ? a->nt : 1, 1);
        b->only = calloc(b->nt ? b->nt : 1, 1);
        if (!a->gid || !b->gid || !a->keys || !b->keys || !a->only || !b->only)
            return GTET_ERR_OUT_OF_MEMORY;
        if ((st = common_ids(a, b, r, &np->side)) != GTET_OK) return st;
        if (r->points_only_a || r->points_only_b) {
            r->kind = GTET_DIFF_POINTS;
            nearest_other(np->side ? a : b, r->first_point_only, np);
            return GTET_OK;
        }
        tet_keys(a);
        tet_keys(b);
        merge(a, b, r);
        if (!r->only_a && !r->only_b) {
            r->kind = GTET_DIFF_IDENTICAL;
            return xyz ? identical_against_input(a, xyz, n, r) : GTET_OK;
        }
    }
    gtet_status sa = check_side(a, xyz, n), sb = check_side(b, xyz, n);
    if (sa == GTET_ERR_OUT_OF_MEMORY || sb == GTET_ERR_OUT_OF_MEMORY) return GTET_ERR_OUT_OF_MEMORY;
    int oka = sa == GTET_OK, okb = sb == GTET_OK;
    if (!oka || !okb || !valid_ids) {
        r->kind = oka ? GTET_DIFF_B_NOT_DELAUNAY : okb ? GTET_DIFF_A_NOT_DELAUNAY
                                                       : GTET_DIFF_NEITHER_DELAUNAY;
        return GTET_OK;
    }
    r->kind = GTET_DIFF_TIES;
    return match_groups(a, b, r);
}

gtet_status gtet_diff(const double *va, size_t nva, const uint32_t *ta, size_t nta,
                      const double *vb, size_t nvb, const uint32_t *tb, size_t ntb,
                      const double *xyz, size_t n, gtet_diff_report *report)
{
    if (!report) return GTET_ERR_ARGUMENT;
    memset(report, 0, sizeof *report);
    report->tets_a = nta;
    report->tets_b = ntb;
    if ((!va && nva) || (!ta && nta) || (!vb && nvb) || (!tb && ntb) || (!xyz && n)) {
        snprintf(report->message, sizeof report->message,
                 "invalid argument: a NULL array with a nonzero count");
        return GTET_ERR_ARGUMENT;
    }
    if (nva >= UINT32_MAX || nvb >= UINT32_MAX || nta >= UINT32_MAX / 4 || ntb >= UINT32_MAX / 4) {
        snprintf(report->message, sizeof report->message, "more vertices or tets than 32-bit ids hold");
        return GTET_ERR_TOO_LARGE;
    }
    side a = {va, nva, ta, nta, NULL, NULL, NULL, NULL, NULL, &report->check_a};
    side b = {vb, nvb, tb, ntb, NULL, NULL, NULL, NULL, NULL, &report->check_b};
    near_point np = {0, 0, {0, 0, 0}, 0};
    gtet_status st = diff_run(&a, &b, xyz, n, report, &np);
    side *s[2] = {&a, &b};
    for (int i = 0; i < 2; i++) {
        free(s[i]->gid);
        free(s[i]->keys);
        free(s[i]->only);
        free(s[i]->cell);
        free(s[i]->cell_hull);
    }
    if (st != GTET_OK) {
        gtet_diff_report_free(report);
        snprintf(report->message, sizeof report->message, "%s", gtet_status_str(st));
        return st;
    }
    verdict(report, &np);
    return GTET_OK;
}
