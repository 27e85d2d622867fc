/* mpi_output.c -- step 7 of gtet_triangulate_mpi: ownership by the smallest vertex id, global
 * tet ids rank by rank, neighbours across ranks by matching facets (proofs/distributed.md D6,
 * D7), the tile's and the used vertices. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

typedef struct frec {
    uint64_t key[3];
    uint64_t tet;    /* global id */
} frec;

static const frec *g_frecs;
static int cmp_frec_idx(const void *a, const void *b)
{
    const frec *x = g_frecs + *(const size_t *)a, *y = g_frecs + *(const size_t *)b;
    for (int k = 0; k < 3; k++)
        if (x->key[k] != y->key[k]) return x->key[k] < y->key[k] ? -1 : 1;
    return x->tet < y->tet ? -1 : x->tet > y->tet;
}

/* a[0..n) by id: LSD radix sort, 8-bit digits, as many as the largest id needs (3 passes up to
 * 2^24 vertices; the tests' few thousand take 2, tiny sets 1), where qsort was 3.5 % of a
 * rank's instructions; -1 out of memory */
static int sort_by_id(mpt *a, size_t n)
{
    uint64_t top = 0;
    for (size_t i = 0; i < n; i++) top = a[i].id > top ? a[i].id : top;
    mpt *b = mx_malloc((n + 1) * sizeof *b);
    if (!b) return -1;
    mpt *src = a, *dst = b;
    for (int sh = 0; sh < 64 && (sh == 0 || (top >> sh) != 0); sh += 8) {
        size_t cnt[257] = {0};
        for (size_t i = 0; i < n; i++) cnt[((src[i].id >> sh) & 0xff) + 1]++;
        for (int d = 0; d < 256; d++) cnt[d + 1] += cnt[d];
        for (size_t i = 0; i < n; i++) dst[cnt[(src[i].id >> sh) & 0xff]++] = src[i];
        mpt *t = src;
        src = dst;
        dst = t;
    }
    if (src != a) memcpy(a, src, n * sizeof *a);
    free(b);
    return 0;
}

#define NOLID UINT32_MAX

gtet_status mx_step_output(run *R, gtet_mpi_result *res)
{
    mctx *c = &R->c;
    int P = c->size, me = c->rank;
    gtet_status s = GTET_OK;
    size_t nt;
    const uint32_t *tv, *nb;
    mx_local_mesh(R, &nt, &tv, &nb);
    size_t m = R->m;
    /* each local tet's index among the owned ones (NOLID: not owned); 4 B, as the neighbour
     * loop reads it at random */
    uint32_t *lid = mx_malloc((nt + 1) * sizeof *lid);
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    vec fr = {NULL, 0, 0, sizeof(frec)};
    vec slot = {NULL, 0, 0, sizeof(uint64_t)};
    frec *sb = NULL, *rb = NULL;
    size_t *ord = NULL, *perm = NULL;
    uint64_t *rep = NULL, *back = NULL;
    /* the vertex ids of S in an array of their own: the tet loops read them at random, and
     * 8 B per vertex stays in cache where the 32 B records do not */
    uint64_t *vid = mx_malloc((R->ns + 1) * sizeof *vid);
    res->tet_offsets = mx_malloc(((size_t)P + 1) * sizeof *res->tet_offsets);
    if (!lid || !scnt || !rcnt || !pos || !vid || !res->tet_offsets)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    size_t own = 0;
    if (s == GTET_OK)
        for (size_t i = 0; i < R->ns; i++) vid[i] = R->sp[i].id;
    if (s == GTET_OK)
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *v = tv + 4 * t;
            uint32_t lo = v[0];
            for (int i = 1; i < 4; i++)
                if (vid[v[i]] < vid[lo]) lo = v[i];
            /* owned: the smallest vertex is in this tile (D6) */
            lid[t] = lo < m ? (uint32_t)own++ : NOLID;
        }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    uint64_t mine = own;
    MPI_Allgather(&mine, 1, MPI_UINT64_T, res->tet_offsets + 1, 1, MPI_UINT64_T, c->comm);
    res->tet_offsets[0] = 0;
    for (int q = 0; q < P; q++) res->tet_offsets[q + 1] += res->tet_offsets[q];
    res->tet_offset = res->tet_offsets[me];
    res->num_tets_global = res->tet_offsets[P];
    res->num_tets = own;
    /* fresh arrays (on huge pages: mx_malloc): 64 B per owned tet, as much new memory as
     * E54's widening of the patched mesh's arrays took, now that the first round's mesh is
     * patched in place (mpi_patch.c, NOTES E80), and no copy */
    res->tets = mx_malloc((4 * own + 1) * sizeof *res->tets);
    res->neighbors = mx_malloc((4 * own + 1) * sizeof *res->neighbors);
    if (!res->tets || !res->neighbors) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
#define SET_NB(o, f, x) (res->neighbors[4 * (o) + (size_t)(f)] = (x))
    for (size_t t = 0; t < nt && s == GTET_OK; t++) {
        if (lid[t] == NOLID) continue;
        size_t o = lid[t];
        const uint32_t *v = tv + 4 * t;
        for (int f = 0; f < 4; f++) {
            res->tets[4 * o + (size_t)f] = vid[v[f]];
            uint32_t u = nb[4 * t + (size_t)f];
            int tilev = 0;
            for (int i = 0; i < 4; i++)
                if (i != f && v[i] < m) tilev = 1;
            if (u != GTET_NO_TET && lid[u] != NOLID) {
                SET_NB(o, f, res->tet_offset + lid[u]);   /* both owned here: final (D7) */
            } else if (u == GTET_NO_TET && tilev) {
                SET_NB(o, f, GTET_MPI_NO_TET);   /* certified hull facet */
            } else {
                frec *r = mx_vec_push(&fr);
                uint64_t *sl = mx_vec_push(&slot);
                if (!r || !sl) {
                    s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
                    break;
                }
                uint64_t k4[4] = {0, 0, 0, 0};
                int j = 1;
                for (int i = 0; i < 4; i++)
                    if (i != f) k4[j++] = vid[v[i]];
                mx_sort4(k4);
                memcpy(r->key, k4 + 1, sizeof r->key);
                r->tet = res->tet_offset + o;
                *sl = 4 * o + (size_t)f;
                SET_NB(o, f, GTET_MPI_NO_TET);
            }
        }
    }
#undef SET_NB
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    /* facet matching: records hashed by their key (D7) */
    size_t nr = fr.n;
    const frec *frs = (const frec *)fr.p;
    int *dst = mx_malloc(nr * sizeof *dst);
    sb = mx_malloc(nr * sizeof *sb);
    perm = mx_malloc(nr * sizeof *perm);
    if (!dst || !sb || !perm) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(dst);
        goto done;
    }
    for (size_t i = 0; i < nr; i++)
        dst[i] = (int)(mx_mix64(frs[i].key[0] ^ mx_mix64(frs[i].key[1] ^ mx_mix64(frs[i].key[2]))) %
                       (uint64_t)P);
    mx_rank_order(dst, nr, P, scnt, pos, perm);
    for (size_t k = 0; k < nr; k++) sb[k] = frs[perm[k]];
    free(dst);
    size_t mr;
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(frec), &r, rcnt, &mr, 0)) != GTET_OK) goto done;
        rb = r;
    }
    ord = mx_malloc(mr * sizeof *ord);
    rep = mx_malloc(mr * sizeof *rep);
    if (!ord || !rep) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < mr; k++) ord[k] = k;
    g_frecs = rb;
    mpi_sort(ord, mr, sizeof *ord, cmp_frec_idx);
    for (size_t a = 0; a < mr && s == GTET_OK;) {
        size_t b = a + 1;
        while (b < mr && !memcmp(rb[ord[a]].key, rb[ord[b]].key, sizeof rb[0].key)) b++;
        if (b - a == 1) {
            rep[ord[a]] = GTET_MPI_NO_TET;   /* one side only: a hull facet */
        } else if (b - a == 2) {
            rep[ord[a]] = rb[ord[a + 1]].tet;
            rep[ord[a + 1]] = rb[ord[a]].tet;
        } else {
            s = mx_fail(c, GTET_ERR_INTERNAL, "facet (%llu, %llu, %llu) is in %zu owned tets",
                        (unsigned long long)rb[ord[a]].key[0],
                        (unsigned long long)rb[ord[a]].key[1],
                        (unsigned long long)rb[ord[a]].key[2], b - a);
        }
        a = b;
    }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    {
        void *r;
        size_t tot;
        if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = r;
    }
    const uint64_t *sls = (const uint64_t *)slot.p;
    uint64_t hull = 0, ghull = 0;
    for (size_t k = 0; k < nr; k++) res->neighbors[sls[perm[k]]] = back[k];
    for (size_t i = 0; i < 4 * own; i++) hull += res->neighbors[i] == GTET_MPI_NO_TET;
    MPI_Allreduce(&hull, &ghull, 1, MPI_UINT64_T, MPI_SUM, c->comm);
    res->num_hull_facets = ghull;
    /* the tile's vertices and the vertices the owned tets use */
    res->num_tile_vertices = m;
    res->tile_vertex_ids = mx_malloc(m * sizeof *res->tile_vertex_ids);
    res->tile_vertices = mx_malloc(3 * m * sizeof *res->tile_vertices);
    uint64_t *used = mx_malloc((R->ns + 1) * sizeof *used);
    if (!res->tile_vertex_ids || !res->tile_vertices || !used) {
        free(used);
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t i = 0; i < m; i++) {
        res->tile_vertex_ids[i] = R->tile[i].id;
        memcpy(res->tile_vertices + 3 * i, R->tile[i].x, 3 * sizeof(double));
    }
    /* the used vertices: marked over S, listed by vertex id */
    uint32_t *slotof = mx_malloc((R->ns + 1) * sizeof *slotof);
    mpt *lst = mx_malloc((R->ns + 1) * sizeof *lst);
    if (!slotof || !lst) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) {
        free(slotof);
        free(lst);
        free(used);
        goto done;
    }
    memset(slotof, 0, (R->ns + 1) * sizeof *slotof);
    for (size_t t = 0; t < nt; t++)
        if (lid[t] != NOLID)
            for (int i = 0; i < 4; i++) slotof[tv[4 * t + i]] = 1;
    size_t w = 0;
    for (size_t i = 0; i < R->ns; i++)
        if (slotof[i]) {
            lst[w] = R->sp[i];
            lst[w].id = R->sp[i].id;
            w++;
        }
    res->num_used_vertices = w;
    res->used_vertex_ids = used;
    res->used_vertices = mx_malloc((3 * w + 1) * sizeof *res->used_vertices);
    if (!res->used_vertices || sort_by_id(lst, w) != 0)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (s == GTET_OK)
        for (size_t i = 0; i < w; i++) {
            used[i] = lst[i].id;
            memcpy(res->used_vertices + 3 * i, lst[i].x, 3 * sizeof(double));
        }
    free(slotof);
    free(lst);
    s = mx_agree(c, s);
done:
    free(vid);
    free(lid);
    free(scnt);
    free(rcnt);
    free(pos);
    free(fr.p);
    free(slot.p);
    free(sb);
    free(rb);
    free(ord);
    free(perm);
    free(rep);
    free(back);
    return s;
}
