/* mpi_patch.c -- a later round's local triangulation without starting over: DT(S u N) from
 * DT(S) by triangulating only the cavity of the new points N (proofs/distributed.md D9).
 *
 * C = the tets of DT(S) some point of N conflicts with, H = its hull facets some point of N
 * conflicts with (exact predicates behind conservative filters).  Every tet of DT(S u N) not in
 * DT(S) has its vertices in W = N u vertices(C) u vertices(H), so it is a tet of DT(W) (D2 on
 * W); they fill the region bounded by the facets shared with the tets kept (DT(S) minus C) and
 * by hull facets, and are found by a flood over DT(W) from the kept tets' cavity facets that
 * never crosses one of those.  Any inconsistency (a cavity facet with no tet of DT(W) on its
 * inner side, a flood that meets a kept tet's facet from the wrong tet, W flat) makes the caller
 * triangulate S u N from scratch instead.  The first round's arrays are patched where they lie
 * (taken from its gtet_mesh): C's slots are filled by the last kept tets, the new tets go after
 * them, so a round costs the size of C and H, not of the mesh (merge, NOTES.md E80).  C and H
 * themselves are found in mpi_cavity.c (mx_find_cavity). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "mesh/mesh.h"
#include "mpi/mpi_patch.h"

/* a map from a facet (3 sorted local vertex ids) to a value, open addressing */
typedef struct fmap {
    uint32_t *k;   /* 4 per slot: 3 ids, value; k[4i] == NONE: empty */
    size_t cap;
} fmap;

static void key3(uint32_t a, uint32_t b, uint32_t c, uint32_t out[3])
{
    if (a > b) { uint32_t t = a; a = b; b = t; }
    if (b > c) { uint32_t t = b; b = c; c = t; }
    if (a > b) { uint32_t t = a; a = b; b = t; }
    out[0] = a;
    out[1] = b;
    out[2] = c;
}

static size_t fm_slot(const fmap *M, const uint32_t k[3])
{
    uint64_t h = mx_mix64(((uint64_t)k[0] << 32 | k[1]) ^ mx_mix64(k[2]));
    size_t j = (size_t)h & (M->cap - 1);
    while (M->k[4 * j] != NONE &&
           (M->k[4 * j] != k[0] || M->k[4 * j + 1] != k[1] || M->k[4 * j + 2] != k[2]))
        j = (j + 1) & (M->cap - 1);
    return j;
}

static void fm_put(fmap *M, const uint32_t k[3], uint32_t v)
{
    size_t j = fm_slot(M, k);
    memcpy(M->k + 4 * j, k, 3 * sizeof *k);
    M->k[4 * j + 3] = v;
}

static uint32_t fm_get(const fmap *M, const uint32_t k[3])
{
    size_t j = fm_slot(M, k);
    return M->k[4 * j] == NONE ? NONE - 1 : M->k[4 * j + 3];
}

/* the facet of tet (tv) opposite slot f, sorted */
static void facet_key(const uint32_t *v, int f, uint32_t out[3])
{
    uint32_t a[3];
    int j = 0;
    for (int i = 0; i < 4; i++)
        if (i != f) a[j++] = v[i];
    key3(a[0], a[1], a[2], out);
}


/* the first t' >= t below nt with cf[t'] & mask: 8 marks at a time past unmarked ones (C and H
 * are a few hundred tets among millions; the byte loops were most of the patch's own time,
 * NOTES.md E224) */
static size_t next_marked(const uint8_t *cf, size_t t, size_t nt, uint8_t mask)
{
    const uint64_t wm = 0x0101010101010101ull * mask;
    while (t < nt && (t & 7)) {
        if (cf[t] & mask) return t;
        t++;
    }
    for (; t + 8 <= nt; t += 8) {
        uint64_t w;
        memcpy(&w, cf + t, sizeof w);
        if (w & wm) break;
    }
    for (; t < nt; t++)
        if (cf[t] & mask) return t;
    return nt;
}

/* the tets t < nt with cf[t] & mask */
static size_t count_marked(const uint8_t *cf, size_t nt, uint8_t mask)
{
    size_t n = 0;
    for (size_t t = next_marked(cf, 0, nt, mask); t < nt; t = next_marked(cf, t + 1, nt, mask)) n++;
    return n;
}

/* W and its triangulation; 1 done, 0 fall back, -1 out of memory */
static int triangulate_w(patch *X)
{
    const run *R = X->R;
    for (size_t i = 0; i < R->ns; i++) X->wid[i] = NONE;
    X->nw = 0;
    for (size_t i = X->n_old; i < R->ns; i++) X->wid[i] = 0;
    for (size_t t = next_marked(X->cf, 0, X->nt, 0xff); t < X->nt;
         t = next_marked(X->cf, t + 1, X->nt, 0xff))
        for (int i = 0; i < 4; i++) X->wid[X->tv[4 * t + i]] = 0;
    for (size_t i = 0; i < R->ns; i++)
        if (X->wid[i] == 0) {
            X->wid[i] = (uint32_t)X->nw;
            X->ws[X->nw++] = (uint32_t)i;
        }
    double *xyz = mx_malloc(3 * X->nw * sizeof *xyz);
    if (!xyz) return -1;
    for (size_t j = 0; j < X->nw; j++) memcpy(xyz + 3 * j, R->sp[X->ws[j]].x, 3 * sizeof(double));
    gtet_options o = R->lopt;
    o.input_done = mx_free_input;
    o.input_done_user = &xyz;
    gtet_status s = gtet_triangulate(xyz, X->nw, &o, &X->wm);
    free(xyz);
    if (s == GTET_ERR_OUT_OF_MEMORY) return -1;
    if (s != GTET_OK || gtet_mesh_num_vertices(X->wm) != X->nw) return 0;
    const uint32_t *map = gtet_mesh_input_map(X->wm);
    for (size_t j = 0; j < X->nw; j++)
        if (map[j] != j) return 0;
    return 1;
}

/* the cavity facets: a kept tet's facet across which the tet is in C or the hull facet is in
 * H -> 4t+f; a hull facet of a tet of C not in H (stays a hull facet) -> NONE.  Found from the
 * marked tets alone (cf != 0: C, and kept tets with a hull facet in H): a kept tet's facet on
 * C is the facet its neighbour in C shares with it, so the work is in C and H, not in the
 * mesh (NOTES.md E80).  1, or 0 if a neighbour link has no way back (fall back) */
static int cavity_facets(const patch *X, fmap *B, size_t *nkept_facets)
{
    *nkept_facets = 0;
    for (size_t t = next_marked(X->cf, 0, X->nt, 0xff); t < X->nt;
         t = next_marked(X->cf, t + 1, X->nt, 0xff)) {
        const uint32_t *v = X->tv + 4 * t;
        int inC = X->cf[t] & 16;
        for (int f = 0; f < 4; f++) {
            uint32_t u = X->nb[4 * t + f], k[3];
            int hullH = u == GTET_NO_TET && ((X->cf[t] >> f) & 1);
            if (!inC) {                               /* kept: its hull facets in H */
                if (!hullH) continue;
                facet_key(v, f, k);
                fm_put(B, k, (uint32_t)(4 * t + (size_t)f));
                ++*nkept_facets;
            } else if (u == GTET_NO_TET) {            /* C's hull facet not in H stays */
                if (hullH) continue;
                facet_key(v, f, k);
                fm_put(B, k, NONE);
            } else if (!(X->cf[u] & 16)) {            /* kept u: its facet facing t */
                int g = 0;
                while (g < 4 && X->nb[4 * (size_t)u + g] != t) g++;
                if (g == 4) return 0;
                facet_key(X->tv + 4 * (size_t)u, g, k);
                fm_put(B, k, 4 * u + (uint32_t)g);
                ++*nkept_facets;
            }
        }
    }
    return 1;
}

/* the tet of DT(W) on the other side of kept tet K's facet f than K (h = 4K + f), or NONE;
 * g: a facet of DT(W) with K's facet's vertices (4 w + slot), or NONE when DT(W) has none */
static uint32_t inner_tet(const patch *X, uint32_t g, uint32_t h)
{
    const mpt *sp = X->R->sp;
    const uint32_t *v = X->tv + 4 * (h / 4), *wt = gtet_mesh_tets(X->wm);
    const uint32_t *wn = gtet_mesh_neighbors(X->wm);
    uint32_t k[3], a[3];
    facet_key(v, (int)(h % 4), k);
    if (g >= NONE - 1) return NONE;
    for (int i = 0; i < 3; i++) a[i] = k[i];
    int sk = gtet_orient3d(sp[a[0]].x, sp[a[1]].x, sp[a[2]].x, sp[v[h % 4]].x);
    uint32_t cand[2] = {g / 4, wn[g] == GTET_NO_TET ? NONE : wn[g]};
    for (int c = 0; c < 2; c++) {
        if (cand[c] == NONE) continue;
        const uint32_t *w = wt + 4 * (size_t)cand[c];
        for (int j = 0; j < 4; j++) {
            uint32_t s = X->ws[w[j]];
            if (s == a[0] || s == a[1] || s == a[2]) continue;
            if (gtet_orient3d(sp[a[0]].x, sp[a[1]].x, sp[a[2]].x, sp[s].x) == -sk && sk != 0)
                return cand[c];
        }
    }
    return NONE;
}

/* bw[j] for each slot j of B: a facet of DT(W) (4 w + slot) with slot j's key, or NONE.  DT(W)'s
 * facets are looked up in B rather than put in a map of their own: B holds the cavity's
 * facets, a few per tet of C, where DT(W) has 4 a tet (a map of those was 16 B x 16 a tet of
 * DT(W), touched at random, NOTES.md E204); the last of DT(W)'s facets with a key is kept, as
 * that map kept it */
static void w_facets(const patch *X, const fmap *B, uint32_t *bw)
{
    size_t nwt = gtet_mesh_num_tets(X->wm);
    const uint32_t *wt = gtet_mesh_tets(X->wm);
    for (size_t j = 0; j < B->cap; j++) bw[j] = NONE;
    for (size_t w = 0; w < nwt; w++) {
        uint32_t sv[4];
        for (int i = 0; i < 4; i++) sv[i] = X->ws[wt[4 * w + i]];
        for (int g = 0; g < 4; g++) {
            uint32_t k[3];
            facet_key(sv, g, k);
            size_t j = fm_slot(B, k);
            if (B->k[4 * j] != NONE) bw[j] = (uint32_t)(4 * w + (size_t)g);
        }
    }
}

/* the flood over DT(W) from the kept cavity facets: fid[w] = its index among the new tets, or
 * NONE; 1 consistent, 0 not (fall back) */
static int flood(const patch *X, const fmap *B, const uint32_t *bw, size_t nkf, uint32_t *fid,
                 uint32_t *stack, size_t *nnew)
{
    size_t nwt = gtet_mesh_num_tets(X->wm), top = 0, linked = 0;
    const uint32_t *wt = gtet_mesh_tets(X->wm);
    const uint32_t *wn = gtet_mesh_neighbors(X->wm);
    *nnew = 0;
    for (size_t w = 0; w < nwt; w++) fid[w] = NONE;
    for (size_t i = 0; i < B->cap; i++) {
        uint32_t h = B->k[4 * i + 3];
        if (B->k[4 * i] == NONE || h == NONE) continue;
        uint32_t w = inner_tet(X, bw[i], h);
        if (w == NONE) return 0;
        if (fid[w] == NONE) {
            fid[w] = (uint32_t)(*nnew)++;
            stack[top++] = w;
        }
    }
    while (top) {
        uint32_t w = stack[--top];
        for (int g = 0; g < 4; g++) {
            uint32_t k[3], sv[4];
            for (int i = 0; i < 4; i++) sv[i] = X->ws[wt[4 * (size_t)w + i]];
            facet_key(sv, g, k);
            size_t j = fm_slot(B, k);
            uint32_t b = B->k[4 * j] == NONE ? NONE - 1 : B->k[4 * j + 3];
            if (b == NONE) {            /* stays a hull facet */
                if (wn[4 * (size_t)w + g] != GTET_NO_TET) return 0;
                continue;
            }
            if (b != NONE - 1) {        /* a kept tet's facet */
                if (inner_tet(X, bw[j], b) != w) return 0;
                linked++;
                continue;
            }
            uint32_t u = wn[4 * (size_t)w + g];
            if (u == GTET_NO_TET || fid[u] != NONE) continue;
            fid[u] = (uint32_t)(*nnew)++;
            stack[top++] = u;
        }
    }
    return linked == nkf;
}

/* room for nt2 tets in R->ptv, R->ptn, with 1/32 more for later rounds' few new tets, each
 * block keeping twice that room for the output's 64-bit rows (R->pcap); the arrays' contents
 * stay as they were whatever happens.  0, or -1 out of memory */
static int reserve_tets(run *R, size_t nt2)
{
    if (nt2 <= R->pcap) return 0;
    size_t cap = nt2 + R->pnt / 32 + 64;
    const size_t bytes = (4 * cap + 1) * sizeof(uint64_t);
    uint32_t *tv = mx_realloc(R->ptv, bytes);
    if (!tv) return -1;
    R->ptv = tv;
    uint32_t *tn = mx_realloc(R->ptn, bytes);
    if (!tn) return -1;
    R->ptn = tn;
    R->pcap = cap;
    return 0;
}

/* the tets the first round's arrays have room for, with the output's room kept: the
 * kernel's (gtet_triangulate_wide) allocation, at least R->pnt */
static size_t taken_room(const run *R)
{
    size_t cap = R->pnt;
#if defined(__GLIBC__)
    size_t u = malloc_usable_size(R->ptv), v = malloc_usable_size(R->ptn);
    if (v < u) u = v;
    if (u >= sizeof(uint64_t) && (u - sizeof(uint64_t)) / 32 > cap)
        cap = (u - sizeof(uint64_t)) / 32;
#endif
    return cap;
}

/* a link from a kept tet into C, cut before the kept tets move (GTET_NO_TET is NONE) */
#define CUT (NONE - 1)

/* the kept tets at or above nk, in order, into the holes C leaves below nk (as many of each):
 * mv[s - nk] = where s went; every link between kept tets is kept pointing at the tet's
 * current slot, as the moved tet's kept neighbours' back-links are redirected with it */
static void compact_kept(uint32_t *tv, uint32_t *tn, const uint8_t *cf, size_t nt, size_t nk,
                         uint32_t *mv)
{
    size_t h = 0;
    for (size_t s = nk; s < nt; s++) {
        mv[s - nk] = NONE;
        if (cf[s] & 16) continue;
        h = next_marked(cf, h, nk, 16);            /* the next hole below nk */
        memcpy(tv + 4 * h, tv + 4 * s, 4 * sizeof *tv);
        memcpy(tn + 4 * h, tn + 4 * s, 4 * sizeof *tn);
        for (int f = 0; f < 4; f++) {
            uint32_t u = tn[4 * h + (size_t)f];
            if (u == GTET_NO_TET || u == CUT) continue;
            for (int g = 0; g < 4; g++)
                if (tn[4 * (size_t)u + g] == (uint32_t)s) tn[4 * (size_t)u + g] = (uint32_t)h;
        }
        mv[s - nk] = (uint32_t)h++;
    }
}

/* DT(S u N) in place: the kept tets compacted into slots 0..nk-1 (compact_kept), the new ones
 * after them; only C's slots, the moved tets and their neighbours' links are written, not the
 * mesh (NOTES.md E80).  1, or -1 out of memory (the arrays then unchanged) */
static int merge(patch *X, const fmap *B, const uint32_t *fid, size_t nnew)
{
    run *R = X->R;
    const uint32_t *wt = gtet_mesh_tets(X->wm), *wn = gtet_mesh_neighbors(X->wm);
    size_t nwt = gtet_mesh_num_tets(X->wm), nt = X->nt, nc = 0;
    nc = count_marked(X->cf, nt, 16);
    size_t nk = nt - nc, nt2 = nk + nnew;
    uint32_t *mv = mx_malloc((nc + 1) * sizeof *mv);
    if (!mv || reserve_tets(R, nt2) != 0) {
        free(mv);
        return -1;
    }
    uint32_t *tv = R->ptv, *tn = R->ptn;
    for (size_t i = 0; i < B->cap; i++) {          /* cut the kept tets' links into C */
        uint32_t b = B->k[4 * i + 3];
        if (B->k[4 * i] != NONE && b != NONE) tn[b] = CUT;
    }
    compact_kept(tv, tn, X->cf, nt, nk, mv);
    for (size_t w = 0; w < nwt; w++) {
        if (fid[w] == NONE) continue;
        size_t o = nk + fid[w];
        uint32_t sv[4];
        for (int i = 0; i < 4; i++) tv[4 * o + i] = sv[i] = X->ws[wt[4 * w + i]];
        for (int g = 0; g < 4; g++) {
            uint32_t k[3];
            facet_key(sv, g, k);
            uint32_t b = fm_get(B, k), u = wn[4 * w + g];
            if (b != NONE && b != NONE - 1) {       /* across a kept tet's cavity facet */
                size_t K = b / 4 < nk ? b / 4 : mv[b / 4 - nk];
                tn[4 * o + g] = (uint32_t)K;
                tn[4 * K + b % 4] = (uint32_t)o;
            } else {
                tn[4 * o + g] = u == GTET_NO_TET ? GTET_NO_TET : (uint32_t)nk + fid[u];
            }
        }
    }
    free(mv);
    R->pnt = nt2;
    R->qfrom = nk;   /* the new tets, made by this round (D3: the kept ones were decided) */
    return 1;
}

/* DT(S u N) from the current local triangulation DT(S), N = S's points from n_old on.
 * *done = 0: the caller must triangulate from scratch (never a wrong mesh: see the file
 * comment). */
gtet_status mx_patch(run *R, size_t n_old, int *done)
{
    mx_upper_clean();   /* after the exchange (E220) */
    patch X;
    memset(&X, 0, sizeof X);
    X.R = R;
    X.n_old = n_old;
    *done = 0;
    if (!R->ptv && gtet_mesh_num_tets(R->mesh) > 0) {
        /* the first patch: the round-1 mesh's arrays become ours, to patch in place */
        R->pnt = gtet_mesh_take_arrays(R->mesh, &R->ptv, &R->ptn);
        R->pcap = taken_room(R);
        gtet_mesh_free(&R->mesh);
        /* room for the later rounds' new tets: the kernel's arrays keep theirs (7 slots a
         * point, build.c, and twice that for the output); a realloc that moved them would
         * copy into new memory (seen at 1M points: a 0.3 s, 56 MB copy) */
        if (reserve_tets(R, R->pnt + 1) != 0)
            return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    }
    mx_local_mesh(R, &X.nt, &X.tv, &X.nb);
    if (!X.tv) return GTET_OK;
    if (n_old == R->ns) {   /* nothing new here (other ranks got points): DT(S) stands */
        *done = 1;
        R->qfrom = X.nt;    /* and every tet of it was decided before */
        return GTET_OK;
    }
    fmap B = {NULL, 0};
    uint32_t *fid = NULL, *stack = NULL, *bw = NULL;
    int ok = -1;
    X.cf = mx_calloc(X.nt + 1, 1);
    X.wid = mx_malloc((R->ns + 1) * sizeof *X.wid);
    X.ws = mx_malloc((R->ns + 1) * sizeof *X.ws);
    if (!X.cf || !X.wid || !X.ws) goto out;
    int fc = mx_find_cavity(&X);
    if (fc != 0) {
        ok = fc > 0 ? 0 : -1;   /* over the growth's budget: from scratch */
        goto out;
    }
    size_t nc = 0;
    nc = count_marked(X.cf, X.nt, 0xff);
    ok = 0;
    if (nc == 0 || nc == X.nt) goto out;          /* nothing found, or nothing kept */
    if ((ok = triangulate_w(&X)) != 1) goto out;
    ok = -1;
    size_t nwt = gtet_mesh_num_tets(X.wm);
    for (B.cap = 64; B.cap < 8 * (4 * nc + 16); B.cap *= 2) {}
    B.k = mx_malloc(4 * B.cap * sizeof *B.k);
    bw = mx_malloc(B.cap * sizeof *bw);
    fid = mx_malloc((nwt + 1) * sizeof *fid);
    stack = mx_malloc((nwt + 1) * sizeof *stack);
    if (!B.k || !bw || !fid || !stack) goto out;
    memset(B.k, 0xff, 4 * B.cap * sizeof *B.k);
    size_t nkf, nnew;
    if (!cavity_facets(&X, &B, &nkf)) {
        ok = 0;
        goto out;
    }
    w_facets(&X, &B, bw);
    ok = flood(&X, &B, bw, nkf, fid, stack, &nnew);
    if (ok == 1) ok = merge(&X, &B, fid, nnew);
    if (ok == 1) *done = 1;
out:
    free(X.cf);
    free(X.wid);
    free(X.ws);
    gtet_mesh_free(&X.wm);
    free(B.k);
    free(bw);
    free(fid);
    free(stack);
    return ok < 0 ? mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory") : GTET_OK;
}
