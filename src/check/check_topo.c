/* check_topo.c -- the combinatorial stages of the checker: facet matching and adjacency, the
 * hull surface, vertex links and the Euler characteristic.
 *
 * Facets are matched by their sorted vertex triple, rebuilt from the tet array alone (never
 * from the mesh's neighbor array, which is only compared with the result): every tet facet is
 * filed under its smallest vertex (a counting sort, linear), and each vertex's small bucket is
 * sorted by the other two vertices.  A facet must be in one tet (a hull facet) or in two tets
 * that induce opposite orientations on it; since both tets are already known to be positively
 * oriented, that says they lie on opposite sides of it.  Two tets with one facet and the same
 * fourth vertex are the same tet.
 *
 * Hull: each hull facet is oriented like its ghost (a,b,c,inf): orient3d(a,b,c,d) < 0 for the
 * tet's fourth vertex d.  Every hull edge must be in exactly two hull facets that traverse it in
 * opposite directions: the hull is a closed oriented surface.
 *
 * Links: the link of vertex v has one vertex per edge at v, one edge per facet at v and one
 * triangle per tet at v.  It must be connected (union-find over the tet corners, joined across
 * rebuilt adjacencies) with Euler characteristic 2 for an interior vertex (a connected closed
 * surface with chi = 2 is a sphere) and 1 for a hull vertex (a connected surface with boundary
 * and chi = 1 is a disk).  The whole complex must have V - E + F - T = 1, as a ball has.
 */
#include <stdlib.h>
#include <string.h>

#include "check_internal.h"

typedef struct fkey {
    uint64_t bc;     /* the two larger vertices of the facet */
    uint32_t apex;   /* the tet's fourth vertex */
    uint32_t tf;     /* 4*t + f */
} fkey;

static int fkey_cmp(const void *pa, const void *pb)
{
    const fkey *a = pa, *b = pb;
    if (a->bc != b->bc) return a->bc < b->bc ? -1 : 1;
    if (a->apex != b->apex) return a->apex < b->apex ? -1 : 1;
    return (a->tf > b->tf) - (a->tf < b->tf);
}

static void sort3(const uint32_t in[3], uint32_t s[3])
{
    uint32_t a = in[0], b = in[1], c = in[2], t;
    if (a > b) { t = a; a = b; b = t; }
    if (b > c) { t = b; b = c; c = t; }
    if (a > b) { t = a; a = b; b = t; }
    s[0] = a;
    s[1] = b;
    s[2] = c;
}

/* Parity of the outward facet relative to its sorted order: 0 even, 1 odd. */
static int facet_parity(const uint32_t o[3])
{
    return (o[0] > o[1]) ^ (o[0] > o[2]) ^ (o[1] > o[2]);
}

static gtet_status check_neighbors(chk_ctx *c)
{
    c->stage = "neighbors";
    for (size_t tf = 0; tf < 4 * c->nt; tf++)
        if (c->neighbors[tf] != c->adj[tf]) {
            size_t t = tf / 4;
            int f = (int)(tf % 4);
            chk_note(c, t, c->neighbors[tf], 4, c->tets + 4 * t);
            if (c->adj[tf] == GTET_NO_TET)
                return chk_fail(c, "neighbor[4*%zu+%d] = %u, but facet %d of tet %zu is on the hull",
                                t, f, c->neighbors[tf], f, t);
            if (c->neighbors[tf] == GTET_NO_TET)
                return chk_fail(c, "neighbor[4*%zu+%d] is the hull, but facet %d of tet %zu is "
                                "shared with tet %u", t, f, f, t, c->adj[tf]);
            return chk_fail(c, "neighbor[4*%zu+%d] = %u, but the tet sharing facet %d of tet %zu "
                            "is %u", t, f, c->neighbors[tf], f, t, c->adj[tf]);
        }
    return GTET_OK;
}

/* Sort small arrays by insertion (the per-vertex buckets hold a few dozen keys), larger ones
 * with qsort.  Keys are distinct (tf is unique), so the order is the same either way. */
static void fkey_sort(fkey *k, size_t n)
{
    if (n > 48) {
        qsort(k, n, sizeof *k, fkey_cmp);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        fkey x = k[i];
        size_t j = i;
        while (j > 0 && fkey_cmp(&k[j - 1], &x) > 0) {
            k[j] = k[j - 1];
            j--;
        }
        k[j] = x;
    }
}

/* The smallest vertex of facet f of tet t (the tet's vertices other than its f-th). */
static uint32_t facet_min(const uint32_t *tet, int f)
{
    uint32_t m = UINT32_MAX;
    for (int i = 0; i < 4; i++)
        if (i != f && tet[i] < m) m = tet[i];
    return m;
}

/* Match the facets filed under vertex v: fill adj for them and count the interior ones.  On a
 * violation return 1, and with report set write it into the report; else 0. */
static int match_bucket(chk_ctx *c, size_t v, const size_t *start, const uint32_t *bucket,
                        fkey *keys, int report, size_t *interior)
{
    const uint32_t *T = c->tets;
    size_t nb = start[v + 1] - start[v];
    for (size_t k = 0; k < nb; k++) {
        uint32_t tf = bucket[start[v] + k], o[3], s[3];
        chk_outward_facet(T + 4 * (tf / 4), (int)(tf % 4), o);
        sort3(o, s);
        keys[k].bc = (uint64_t)s[1] << 32 | s[2];
        keys[k].apex = T[tf];
        keys[k].tf = tf;
    }
    fkey_sort(keys, nb);
    for (size_t g = 0; g < nb;) {
        size_t e = g + 1;
        while (e < nb && keys[e].bc == keys[g].bc) e++;
        uint32_t b = (uint32_t)(keys[g].bc >> 32), cc = (uint32_t)keys[g].bc;
        for (size_t k = g + 1; k < e; k++)
            if (keys[k].apex == keys[k - 1].apex) {
                if (report) {
                    chk_note(c, keys[k - 1].tf / 4, keys[k].tf / 4, 4, T + 4 * (keys[k].tf / 4));
                    chk_fail(c, "tets %u and %u have the same four vertices (%zu %u %u %u)",
                             keys[k - 1].tf / 4, keys[k].tf / 4, v, b, cc, keys[k].apex);
                }
                return 1;
            }
        if (e - g > 2) {
            if (report) {
                uint32_t f3[3] = {(uint32_t)v, b, cc};
                chk_note(c, keys[g].tf / 4, keys[g + 1].tf / 4, 3, f3);
                chk_fail(c, "facet (%zu %u %u) is in %zu tets (%u, %u, %u%s)", v, b, cc, e - g,
                         keys[g].tf / 4, keys[g + 1].tf / 4, keys[g + 2].tf / 4,
                         e - g > 3 ? ", ..." : "");
            }
            return 1;
        }
        if (e - g == 1) {
            c->adj[keys[g].tf] = GTET_NO_TET;
        } else {
            uint32_t t1 = keys[g].tf, t2 = keys[g + 1].tf, o1[3], o2[3];
            chk_outward_facet(T + 4 * (t1 / 4), (int)(t1 % 4), o1);
            chk_outward_facet(T + 4 * (t2 / 4), (int)(t2 % 4), o2);
            if (facet_parity(o1) == facet_parity(o2)) {
                if (report) {
                    uint32_t f3[3] = {(uint32_t)v, b, cc};
                    chk_note(c, t1 / 4, t2 / 4, 3, f3);
                    chk_fail(c, "tets %u and %u lie on the same side of their common facet "
                             "(%zu %u %u): they overlap", t1 / 4, t2 / 4, v, b, cc);
                }
                return 1;
            }
            c->adj[t1] = t2 / 4;
            c->adj[t2] = t1 / 4;
            (*interior)++;
        }
        g = e;
    }
    return 0;
}

/* The buckets are matched in parallel: each facet is in one bucket, so the threads write
 * disjoint entries of adj; each thread keeps its smallest failing vertex, and the failure
 * reported is the one of the smallest vertex over all, found again serially for its message:
 * the same for any thread count. */
gtet_status chk_facets(chk_ctx *c)
{
    const uint32_t *T = c->tets;
    size_t nf = 4 * c->nt;
    gtet_status st = GTET_OK;
    c->stage = "facets";
    size_t *start = calloc(c->nv + 1, sizeof *start);
    uint32_t *bucket = malloc(nf * sizeof *bucket);
    fkey *keys = NULL;
    c->adj = malloc(nf * sizeof *c->adj);
    if (!start || !bucket || !c->adj) {
        st = chk_oom(c);
        goto done;
    }
    /* counting sort of the facets by their smallest vertex */
    for (size_t tf = 0; tf < nf; tf++) {
        if (chk_stop_serial(c, tf)) {
            st = chk_cancelled(c);
            goto done;
        }
        start[facet_min(T + 4 * (tf / 4), (int)(tf % 4)) + 1]++;
    }
    size_t maxb = 0;
    for (size_t v = 0; v < c->nv; v++) {
        if (start[v + 1] > maxb) maxb = start[v + 1];
        start[v + 1] += start[v];
    }
    for (size_t tf = 0; tf < nf; tf++) {
        if (chk_stop_serial(c, tf)) {
            st = chk_cancelled(c);
            goto done;
        }
        bucket[start[facet_min(T + 4 * (tf / 4), (int)(tf % 4))]++] = (uint32_t)tf;
    }
    for (size_t v = c->nv; v > 0; v--) start[v] = start[v - 1];  /* undo the fill's shift */
    start[0] = 0;
    size_t bad = SIZE_MAX, interior = 0;
    int oom = 0;
#pragma omp parallel num_threads(c->threads) reduction(min : bad) reduction(+ : interior) \
    reduction(| : oom) if (c->nt > 8192)
    {
        fkey *k = malloc((maxb ? maxb : 1) * sizeof *k);
        if (!k) oom = 1;
#pragma omp for schedule(dynamic, 1024)
        for (size_t v = 0; v < c->nv; v++)
            if (k && v < bad && !chk_stop(c, v) &&
                match_bucket(c, v, start, bucket, k, 0, &interior))
                bad = v;
        free(k);
    }
    if (oom) {
        st = chk_oom(c);
        goto done;
    }
    if (chk_is_cancelled(c)) {  /* a skipped vertex may hide the first violation */
        st = chk_cancelled(c);
        goto done;
    }
    if (bad != SIZE_MAX) {
        keys = malloc((maxb ? maxb : 1) * sizeof *keys);
        if (!keys) st = chk_oom(c);
        else {
            match_bucket(c, bad, start, bucket, keys, 1, &interior);
            st = GTET_ERR_CHECK_FAILED;
        }
        goto done;
    }
    c->interior_facets = interior;
    if (c->neighbors && (st = check_neighbors(c)) != GTET_OK) goto done;
    /* the hull facets, in order of their tet facet */
    c->stage = "hull_surface";
    c->nh = 0;
    for (size_t tf = 0; tf < nf; tf++) c->nh += c->adj[tf] == GTET_NO_TET;
    if (c->nh < 4) {
        st = chk_fail(c, "the mesh has %zu hull facets; a closed hull needs at least 4", c->nh);
        goto done;
    }
    c->hull = malloc(3 * c->nh * sizeof *c->hull);
    c->hull_tf = malloc(c->nh * sizeof *c->hull_tf);
    if (!c->hull || !c->hull_tf) {
        st = chk_oom(c);
        goto done;
    }
    for (size_t tf = 0, h = 0; tf < nf; tf++)
        if (c->adj[tf] == GTET_NO_TET) {
            chk_outward_facet(T + 4 * (tf / 4), (int)(tf % 4), c->hull + 3 * h);
            c->hull_tf[h++] = (uint32_t)tf;
        }
    c->report->hull_facets = c->nh;
done:
    free(start);
    free(bucket);
    free(keys);
    return st;
}

typedef struct ekey {
    uint32_t u, w;   /* u < w */
    uint32_t h;      /* hull facet */
    uint8_t i;       /* edge (hull[3h+i], hull[3h+(i+1)%3]) */
    uint8_t fwd;     /* 1 when the facet traverses it from u to w */
} ekey;

static int ekey_cmp(const void *pa, const void *pb)
{
    const ekey *a = pa, *b = pb;
    if (a->u != b->u) return a->u < b->u ? -1 : 1;
    if (a->w != b->w) return a->w < b->w ? -1 : 1;
    return (a->h > b->h) - (a->h < b->h);
}

gtet_status chk_hull_surface(chk_ctx *c)
{
    size_t ne = 3 * c->nh;
    ekey *e = malloc(ne * sizeof *e);
    c->hull_adj = malloc(ne * sizeof *c->hull_adj);
    if (!e || !c->hull_adj) {
        free(e);
        return chk_oom(c);
    }
    for (size_t h = 0; h < c->nh; h++)
        for (int i = 0; i < 3; i++) {
            uint32_t a = c->hull[3 * h + i], b = c->hull[3 * h + (i + 1) % 3];
            ekey *k = &e[3 * h + i];
            k->u = a < b ? a : b;
            k->w = a < b ? b : a;
            k->h = (uint32_t)h;
            k->i = (uint8_t)i;
            k->fwd = a < b;
        }
    qsort(e, ne, sizeof *e, ekey_cmp);
    gtet_status st = GTET_OK;
    c->stage = "hull_surface";
    for (size_t g = 0; g < ne;) {
        size_t x = g + 1;
        while (x < ne && e[x].u == e[g].u && e[x].w == e[g].w) x++;
        if (x - g != 2) {
            uint32_t ed[2] = {e[g].u, e[g].w};
            chk_note(c, c->hull_tf[e[g].h] / 4, GTET_CHECK_NONE, 2, ed);
            st = chk_fail(c, "hull edge (%u %u) is in %zu hull facet%s, not 2: the hull is not a "
                          "closed surface", e[g].u, e[g].w, x - g, x - g == 1 ? "" : "s");
            break;
        }
        if (e[g].fwd == e[g + 1].fwd) {
            const uint32_t *h1 = c->hull + 3 * (size_t)e[g].h, *h2 = c->hull + 3 * (size_t)e[g + 1].h;
            chk_note(c, c->hull_tf[e[g].h] / 4, c->hull_tf[e[g + 1].h] / 4, 3, h1);
            st = chk_fail(c, "hull facets (%u %u %u) and (%u %u %u) traverse their common edge in "
                          "the same direction: the hull is not consistently oriented",
                          h1[0], h1[1], h1[2], h2[0], h2[1], h2[2]);
            break;
        }
        c->hull_adj[3 * (size_t)e[g].h + e[g].i] = e[g + 1].h;
        c->hull_adj[3 * (size_t)e[g + 1].h + e[g + 1].i] = e[g].h;
        g = x;
    }
    free(e);
    return st;
}

static int cmp_u32(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return (a > b) - (a < b);
}

/* Insertion sort for the small per-vertex edge buckets, qsort for large ones. */
static void u32_sort(uint32_t *a, size_t n)
{
    if (n > 64) {
        qsort(a, n, sizeof *a, cmp_u32);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        uint32_t x = a[i];
        size_t j = i;
        while (j > 0 && a[j - 1] > x) {
            a[j] = a[j - 1];
            j--;
        }
        a[j] = x;
    }
}

/* Distinct edges at each vertex (n_edges) and in all (returned): each edge filed under its
 * smaller vertex, each vertex's bucket sorted.  start: nv + 1 zeros; other: 6 nt entries. */
static int64_t count_edges(chk_ctx *c, int64_t *n_edges, size_t *start, uint32_t *other)
{
    const uint32_t *T = c->tets;
    const size_t nv = c->nv, nt = c->nt;
    static const int ep[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for (size_t t = 0; t < nt; t++) {
        if (chk_stop_serial(c, t)) return 0;  /* the caller looks at the flag */
        for (int k = 0; k < 6; k++) {
            uint32_t a = T[4 * t + ep[k][0]], b = T[4 * t + ep[k][1]];
            start[(a < b ? a : b) + 1]++;
        }
    }
    for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
    for (size_t t = 0; t < nt; t++) {
        if (chk_stop_serial(c, t)) return 0;
        for (int k = 0; k < 6; k++) {
            uint32_t a = T[4 * t + ep[k][0]], b = T[4 * t + ep[k][1]];
            other[start[a < b ? a : b]++] = a < b ? b : a;
        }
    }
    for (size_t v = nv; v > 0; v--) start[v] = start[v - 1];
    start[0] = 0;
    /* buckets in parallel; the counts are sums of increments (atomic for the other end), so
     * they do not depend on the thread count */
    int64_t E = 0;
#pragma omp parallel for num_threads(c->threads) reduction(+ : E) schedule(dynamic, 1024) \
    if (nt > 8192)
    for (size_t v = 0; v < nv; v++) {
        if (chk_stop(c, v)) continue;  /* the caller looks at the flag */
        u32_sort(other + start[v], start[v + 1] - start[v]);
        int64_t mine = 0;
        for (size_t k = start[v]; k < start[v + 1]; k++)
            if (k == start[v] || other[k] != other[k - 1]) {
                mine++;
#pragma omp atomic
                n_edges[other[k]]++;
            }
        E += mine;
#pragma omp atomic
        n_edges[v] += mine;
    }
    return E;
}

/* Facets (each once) and tets at each vertex, hull vertices, and the components of each
 * vertex's link: a union-find over the tet corners (parent: 4 nt entries), two corners of one
 * vertex joined across every interior facet.  Returns the number of facets. */
static int64_t count_facets_and_links(chk_ctx *c, int64_t *n_facets, int64_t *n_tets,
                                      int64_t *n_comp, uint32_t *parent, uint8_t *on_hull)
{
    const uint32_t *T = c->tets;
    const size_t nt = c->nt;
    int64_t F = 0;
    for (size_t x = 0; x < 4 * nt; x++) parent[x] = (uint32_t)x;
    for (size_t t = 0; t < nt; t++) {
        if (chk_stop_serial(c, t)) return 0;  /* the caller looks at the flag */
        for (int f = 0; f < 4; f++) {
            n_tets[T[4 * t + f]]++;
            uint32_t u = c->adj[4 * t + f];
            if (u != GTET_NO_TET && u < t) continue;  /* counted from the other side */
            F++;
            for (int i = 0; i < 4; i++) {
                if (i == f) continue;
                n_facets[T[4 * t + i]]++;
                if (u == GTET_NO_TET) {
                    on_hull[T[4 * t + i]] = 1;
                    continue;
                }
                for (int j = 0; j < 4; j++)
                    if (T[4 * (size_t)u + j] == T[4 * t + i]) {
                        uint32_t r1 = chk_find(parent, (uint32_t)(4 * t + i));
                        uint32_t r2 = chk_find(parent, 4 * u + (uint32_t)j);
                        if (r1 != r2) parent[r1 > r2 ? r1 : r2] = r1 > r2 ? r2 : r1;
                    }
            }
        }
    }
    for (size_t x = 0; x < 4 * nt; x++) {
        if (chk_stop_serial(c, x)) return 0;
        if (chk_find(parent, (uint32_t)x) == x) n_comp[T[x]]++;
    }
    return F;
}

/* Every vertex in a tet has a link of one piece with Euler characteristic 2 (a sphere, inside)
 * or 1 (a disk, on the hull); *nused counts those vertices. */
static gtet_status judge_links(chk_ctx *c, const int64_t *n_edges, const int64_t *n_facets,
                               const int64_t *n_tets, const int64_t *n_comp,
                               const uint8_t *on_hull, int64_t *nused)
{
    *nused = 0;
    for (size_t v = 0; v < c->nv; v++) {
        if (c->unused && c->unused[v]) continue;  /* in no tet (a copy, chk_inputs) */
        (*nused)++;
        uint32_t id = (uint32_t)v;
        if (n_comp[v] != 1) {
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &id);
            return chk_fail(c, "the link of vertex %zu falls into %lld pieces: the tets around "
                            "it do not form one ball", v, (long long)n_comp[v]);
        }
        int64_t chi = n_edges[v] - n_facets[v] + n_tets[v];
        int64_t want = on_hull[v] ? 1 : 2;
        if (chi != want) {
            chk_note(c, GTET_CHECK_NONE, GTET_CHECK_NONE, 1, &id);
            return chk_fail(c, "the link of %s vertex %zu has Euler characteristic %lld, not "
                            "%lld: it is not a %s", on_hull[v] ? "hull" : "interior", v,
                            (long long)chi, (long long)want, on_hull[v] ? "disk" : "sphere");
        }
    }
    return GTET_OK;
}

gtet_status chk_euler_links(chk_ctx *c)
{
    size_t nv = c->nv, nt = c->nt;
    gtet_status st = GTET_OK;
    /* per vertex: edges, facets, tets at it; link components; hull flag */
    int64_t *cnt = calloc(4 * nv, sizeof *cnt);
    size_t *start = calloc(nv + 1, sizeof *start);
    uint32_t *other = malloc(6 * nt * sizeof *other);
    uint32_t *parent = malloc(4 * nt * sizeof *parent);
    uint8_t *on_hull = calloc(nv, 1);
    if (!cnt || !start || !other || !parent || !on_hull) {
        st = chk_oom(c);
        goto done;
    }
    c->stage = "links";
    int64_t *n_edges = cnt, *n_facets = cnt + nv, *n_tets = cnt + 2 * nv, *n_comp = cnt + 3 * nv;
    const int64_t E = count_edges(c, n_edges, start, other);
    if (chk_is_cancelled(c)) {
        st = chk_cancelled(c);
        goto done;
    }
    const int64_t F = count_facets_and_links(c, n_facets, n_tets, n_comp, parent, on_hull);
    if (chk_is_cancelled(c)) {
        st = chk_cancelled(c);
        goto done;
    }
    int64_t nused = 0;
    st = judge_links(c, n_edges, n_facets, n_tets, n_comp, on_hull, &nused);
    if (st != GTET_OK) goto done;
    int64_t euler = nused - E + F - (int64_t)nt;
    c->report->euler = (int)euler;
    c->stage = "euler";
    if (euler != 1)
        st = chk_fail(c, "V - E + F - T = %lld - %lld + %lld - %zu = %lld, not 1: the tets do not "
                      "form a ball", (long long)nused, (long long)E, (long long)F, nt,
                      (long long)euler);
done:
    free(cnt);
    free(start);
    free(other);
    free(parent);
    free(on_hull);
    return st;
}
