/* mpi_output.c -- step 7 of gtet_triangulate_mpi: ownership by the smallest vertex id, global
 * tet ids rank by rank, neighbours across ranks by matching facets (proofs/distributed.md D6,
 * D7), the tile's and the used vertices. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "base/base.h"
#include "mesh/mesh.h"
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

/* the tet loops below read vid[] (by vertex) and lid[] (by neighbour) at random, a cache miss
 * each on a big mesh: the rows OPF tets ahead are asked for while the current one is worked on */
#define OPF 16

/* a vertex of the used list: its id and its index in S */
typedef struct idpos {
    uint64_t id, i;
} idpos;

/* The used vertices by id into ids[0..n) and xyz[0..3n) (coordinates from R->sp): an LSD radix
 * sort of a[0..n) (b: room for n more), 11-bit digits, as many as the largest id needs (2
 * passes up to 2^22 vertices, 3 up to 2^33; NOTES.md E206: 8-bit digits took 3 passes from 2^16
 * on; qsort was 3.5 % of a rank's instructions).  The pairs are 16 B where S's records are 32,
 * and the last pass writes the result itself (NOTES.md E217).  -1 out of memory */
#define RADIX_BITS 11
static int sort_used(const run *R, idpos *a, idpos *b, size_t n, uint64_t *ids, double *xyz)
{
    uint64_t top = 0;
    for (size_t i = 0; i < n; i++) top = a[i].id > top ? a[i].id : top;
    size_t *cnt = mx_malloc(((1u << RADIX_BITS) + 1) * sizeof *cnt);
    if (!cnt) return -1;
    const uint64_t mask = (1u << RADIX_BITS) - 1;
    idpos *src = a, *dst = b;
    for (int sh = 0;; sh += RADIX_BITS) {
        int last = sh + RADIX_BITS >= 64 || (top >> (sh + RADIX_BITS)) == 0;
        memset(cnt, 0, ((1u << RADIX_BITS) + 1) * sizeof *cnt);
        for (size_t i = 0; i < n; i++) cnt[((src[i].id >> sh) & mask) + 1]++;
        for (size_t d = 0; d < mask + 1; d++) cnt[d + 1] += cnt[d];
        if (!last) {
            for (size_t i = 0; i < n; i++) dst[cnt[(src[i].id >> sh) & mask]++] = src[i];
            idpos *t = src;
            src = dst;
            dst = t;
            continue;
        }
        for (size_t i = 0; i < n; i++) {
            if (i + OPF < n) __builtin_prefetch(&R->sp[src[i + OPF].i]);
            size_t k = cnt[(src[i].id >> sh) & mask]++;
            ids[k] = src[i].id;
            memcpy(xyz + 3 * k, R->sp[src[i].i].x, 3 * sizeof(double));
        }
        break;
    }
    free(cnt);
    return 0;
}
#undef RADIX_BITS

#define NOLID UINT32_MAX
/* a 32-bit result's hull neighbour is the compaction's NOLID as it stands */
_Static_assert(NOLID == GTET_MPI_NO_TET32, "NOLID is the 32-bit result's GTET_MPI_NO_TET32");


/* Step 7 writes its result over the local mesh (NOTES.md E120, E130).  The owned tets' rows
 * are first moved down in place in both uint32 arrays (row o of owned tet t, o <= t: a row is
 * read before any later row lands on it): vertex ids stay local, a neighbour becomes its owned
 * index (NOLID: the hull, or a facet the matching fills in).  Then each array is widened to its
 * 64-bit result, back to front, so row o's 32 bytes land at or above where its 16 bytes were
 * read.  Each array's block has the room for that: the local triangulation's arrays are
 * allocated with it (gtet_triangulate_wide) and the patch keeps it (mpi_patch.c
 * reserve_tets); should a block lack it, the array grows in place when the memory after it is
 * free (can_grow), else it is widened into fresh memory.  Memory first touched is costly
 * (NOTES.md Q14): an array widened where it lies takes 16 B an owned tet of fresh memory, a
 * fresh result 32.  A 32-bit result (gtet_mpi_options.id_bits 32, when every id fits) needs no
 * widening: the compaction writes its rows final, global vertex ids and global tet ids, and the
 * arrays are the result (NOTES.md E250, E251). */
typedef struct outx {
    uint32_t *lid;      /* local tet -> owned index, or NOLID */
    const uint64_t *vid;/* local vertex -> global id */
    uint8_t *used;      /* local vertex used by an owned tet */
    vec fr, slot;       /* facets to match across ranks; where their answer goes */
    int w32;            /* the 32-bit result: the rows are written final (global ids) */
    uint64_t nolid;     /* w32: the NOLID neighbours written (as widen counts them) */
} outx;

/* owned tet t (index o): its neighbours encoded into row o of nb (the owned index across, or
 * NOLID), a facet record for each one decided elsewhere, its vertices marked used; then its
 * vertex row moved to row o of tv.  With X->w32 the rows are the 32-bit result's instead
 * (every id fits, ids32_fits): the neighbour across is its global tet id off + owned index,
 * the vertices their global ids, so no later pass reads the rows again.  -1 out of memory */
static int compact_tet(const run *R, outx *X, uint32_t *tv, uint32_t *nb, size_t t, uint64_t off)
{
    size_t m = R->m, o = X->lid[t];
    uint32_t v[4], n[4];
    memcpy(v, tv + 4 * t, sizeof v);
    memcpy(n, nb + 4 * t, sizeof n);
    unsigned tile = 0;   /* bit i: vertex i is a tile point */
    for (int i = 0; i < 4; i++) tile |= (unsigned)(v[i] < m) << i;
    for (int f = 0; f < 4; f++) {
        X->used[v[f]] = 1;
        uint32_t u = n[f];
        int tilev = (tile & ~(1u << f)) != 0;   /* facet f has a tile vertex */
        if (u != GTET_NO_TET && X->lid[u] != NOLID) {
            /* both owned here: final (D7) */
            nb[4 * o + (size_t)f] = X->w32 ? (uint32_t)off + X->lid[u] : X->lid[u];
        } else {
            nb[4 * o + (size_t)f] = NOLID;            /* a certified hull facet, or ... */
            X->nolid++;
            if (u == GTET_NO_TET && tilev) continue;
            frec *r = mx_vec_push(&X->fr);            /* ... matched across ranks */
            uint64_t *sl = mx_vec_push(&X->slot);
            if (!r || !sl) return -1;
            uint64_t k4[4] = {0, 0, 0, 0};
            int j = 1;
            for (int i = 0; i < 4; i++)
                if (i != f) k4[j++] = X->vid[v[i]];
            mx_sort4(k4);
            memcpy(r->key, k4 + 1, sizeof r->key);
            r->tet = off + o;
            *sl = 4 * o + (size_t)f;
        }
    }
    if (X->w32)
        for (int i = 0; i < 4; i++) v[i] = (uint32_t)X->vid[v[i]];
    memcpy(tv + 4 * o, v, sizeof v);
    return 0;
}

/* dst[4o + i] (64-bit) from src[4o + i] (uint32), o from own - 1 down to 0: dst may be src
 * itself (32 bytes a row written at or above the 16 read; through memcpy, as the same bytes are
 * read as uint32 and written as uint64) or separate.  Vertices: their global ids; neighbours:
 * off + owned index, or GTET_MPI_NO_TET, counted in *nolid (the hull facets' count starts
 * there, match_facets) */
static void widen(void *dst, const void *src, size_t own, const uint64_t *vid, uint64_t off,
                  uint64_t *nolid)
{
    unsigned char *d = dst;
    const unsigned char *s = src;
    uint64_t none = 0;
    for (size_t k = 4 * own; k-- > 0;) {
        uint32_t x;
        if (vid) {
            if (k >= 4 * OPF) {   /* below every byte written yet (8k > 4k) */
                memcpy(&x, s + 4 * (k - 4 * OPF), sizeof x);
                __builtin_prefetch(vid + x);
            }
            memcpy(&x, s + 4 * k, sizeof x);
            uint64_t y = vid[x];
            memcpy(d + 8 * k, &y, sizeof y);
        } else {
            memcpy(&x, s + 4 * k, sizeof x);
            none += x == NOLID;
            uint64_t y = x == NOLID ? GTET_MPI_NO_TET : off + x;
            memcpy(d + 8 * k, &y, sizeof y);
        }
    }
    *nolid = none;
}

/* the global counts leave every vertex id and global tet id below GTET_MPI_NO_TET32 (the
 * environment variable GTET_MPI_IDS32_LIMIT=N lowers the largest count allowed to N, for
 * the tests of the fallback); the same answer on every rank, from global figures */
static int ids32_fits(uint64_t vertices, uint64_t tets)
{
    uint64_t lim = (uint64_t)GTET_MPI_NO_TET32 - 1;
    const char *e = getenv("GTET_MPI_IDS32_LIMIT");
    if (e && *e) {
        char *end;
        unsigned long long v = strtoull(e, &end, 10);
        if (!*end && v < lim) lim = v;
    }
    return vertices <= lim && tets <= lim;
}

/* the 32-bit result: the compacted rows, already final (compact_tet), given back what lies
 * above them (the kernel's slots and the 64-bit room, never written by the output) */
static void take_rows32(run *R, gtet_mpi_result *res, size_t own)
{
    size_t bytes = (4 * own + 1) * sizeof(uint32_t);
    uint32_t *a = realloc(R->ptv, bytes), *b = realloc(R->ptn, bytes);
    res->tets32 = a ? a : R->ptv;   /* a failed shrink leaves the block as it was */
    res->neighbors32 = b ? b : R->ptn;
    R->ptv = R->ptn = NULL;
}

/* can block p (of the heap) grow in place to `bytes`?  With glibc: when the blocks after it are
 * free, as far as it needs -- known when a block of exactly the missing size, asked for, is
 * handed out right where p ends (then freed again; glibc grows a block in place into a free
 * next block).  Only speed depends on the answer: a realloc that moved would copy into 4 KiB
 * pages (NOTES.md E120) */
static int can_grow(void *p, size_t bytes)
{
#if defined(__GLIBC__)
    if (!p) return 0;
    size_t u = malloc_usable_size(p);
    if (u >= bytes) return 1;
    void *q = malloc(bytes - u - 8);
    int ok = q && (uintptr_t)q == (uintptr_t)p + u + 8;
    free(q);
    return ok;
#else
    (void)p;
    (void)bytes;
    return 0;
#endif
}

/* one array's result: widened in place when its block has the room or can grow (can_grow),
 * else into fresh memory (huge pages: mx_malloc); *a handed over.  -1 out of memory (*a then
 * still R's) */
static int widen_one(uint32_t **a, uint64_t **out, size_t own, const uint64_t *vid, uint64_t off,
                     uint64_t *nolid)
{
    size_t bytes = (4 * own + 1) * sizeof(uint64_t);
    int inplace = can_grow(*a, bytes);
    uint64_t *r = inplace ? mx_realloc(*a, bytes) : mx_malloc(bytes);
    if (!r) return -1;
    widen(r, inplace ? (void *)r : (void *)*a, own, vid, off, nolid);
    if (!inplace) free(*a);
    *a = NULL;
    *out = r;
    return 0;
}

/* can the block of a hold `bytes` where it lies (the room gtet_triangulate_wide leaves)? */
static int has_room(void *a, size_t bytes)
{
#if defined(__GLIBC__)
    return a && malloc_usable_size(a) >= bytes;
#else
    (void)a;
    (void)bytes;
    return 0;
#endif
}

/* The result's room (NOTES.md E221): the pages above the compacted rows that the widening
 * writes, in R->ptv's block, then in R->ptn's, take the written pages of dead blocks instead of
 * fresh ones (mx_pages_move): the arrays the output no longer reads (S, the sort's buffers, and
 * once the tets are widened the vertex ids), and blocks of the heap's free memory.  The
 * blocks are kept until the widening is done (freed, their pages mapped afresh would be handed
 * out again at once) and then freed.  With 4 KiB pages only (there a
 * fresh page is a fault, a zeroing and, on this kind of guest, a host fault: Q14), and not with
 * GTET_MPI_DONATE=off. */
#define LEND_MAX 64
typedef struct lender {
    const run *R;
    size_t own;
    int on;
    void *blk[LEND_MAX];      /* the blocks lent, freed by lend_end */
    size_t n;
} lender;

static void lend_init(lender *L, const run *R, size_t own)
{
    L->R = R;
    L->own = own;
    L->n = 0;
    L->on = mx_env_mode("GTET_MPI_DONATE") >= 0 && base_page_mode() == BASE_PAGES_SMALL;
}

/* block p of `bytes` lends its written pages to the room; pages moved, -1 when p could not be
 * mapped again (it is then left alone: a leak, not a fault) */
static long lend_pages(lender *L, void *p, size_t bytes)
{
    /* the compacted rows hold the array's first 16 B an owned tet; what lies above them up to
     * the widened size is dead (kernel slots) or never written */
    const size_t live = 4 * L->own * sizeof(uint32_t), room = (4 * L->own + 1) * sizeof(uint64_t);
    uint32_t *const to[2] = {L->R->ptv, L->R->ptn};
    long moved = 0;
    for (int k = 0; k < 2 && L->on && p; k++)
        if (has_room(to[k], room)) {
            long r = mx_pages_move(p, bytes, (char *)to[k] + live, room - live);
            if (r < 0) return -1;
            moved += r;
        }
    return moved;
}

/* the dead block p: its pages lent, the block kept until lend_end (freed now when nothing was
 * lent or the list is full).  -1 as lend_pages */
static int lend(lender *L, void *p, size_t bytes)
{
    long r = lend_pages(L, p, bytes);
    if (r < 0) return -1;
    if (r > 0 && L->n < LEND_MAX)
        L->blk[L->n++] = p;
    else
        free(p);
    return 0;
}

/* the heap's free memory lent: blocks of 64 MiB, halved whenever one has no written page to
 * lend (it came from fresh memory, or the room is full), down to 256 KiB.  -1 as lend_pages */
static int lend_free_memory(lender *L)
{
    for (size_t sz = (size_t)64 << 20; L->on && sz >= ((size_t)256 << 10) && L->n < LEND_MAX;) {
        void *p = malloc(sz);
        long r = p ? lend_pages(L, p, sz) : 0;
        if (r < 0) return -1;
        if (r > 0) {
            L->blk[L->n++] = p;
        } else {
            free(p);
            sz /= 2;
        }
    }
    return 0;
}

static void lend_end(lender *L)
{
    for (size_t i = 0; i < L->n; i++) free(L->blk[i]);
    L->n = 0;
}

/* what only the rounds read (the sets of ids held and sent, the tile grid, the last round's
 * query keys, the owners of S) freed before the output allocates: its arrays can take those
 * blocks instead of fresh memory (NOTES.md Q14, E121) */
static void release_rounds(run *R)
{
    free(R->have.k);
    free(R->sent.k);
    free(R->sent_any);
    R->sent_any = NULL;
    memset(&R->have, 0, sizeof R->have);
    memset(&R->sent, 0, sizeof R->sent);
    free(R->gr.start);
    free(R->gr.cb);
    free(R->gr.bb);
    free(R->gr.far);
    R->gr.start = NULL;
    R->gr.cb = NULL;
    R->gr.bb = NULL;
    R->gr.far = NULL;
    free(R->prev);
    R->prev = NULL;
    R->nprev = 0;
    free(R->sown);
    R->sown = NULL;
}

/* the local mesh's arrays as R->ptv, R->ptn (taken from the first round's gtet_mesh when no
 * later round patched them); *nt tets */
static void take_local(run *R, size_t *nt)
{
    if (!R->ptv && R->mesh) {
        R->pnt = R->pcap = gtet_mesh_take_arrays(R->mesh, &R->ptv, &R->ptn);
    }
    gtet_mesh_free(&R->mesh);
    *nt = R->ptv ? R->pnt : 0;
}

/* the facets decided elsewhere (X->fr): records hashed by their key to a rank, which pairs
 * them (two records: the two tets; one: a hull facet) and answers; the answers go into
 * res->neighbors at X->slot (D7).  nolid: the neighbours GTET_MPI_NO_TET before (the
 * certified hull facets and the slots answered here).  Collective; the agreed status */
static gtet_status match_facets(mctx *c, const outx *X, uint64_t nolid, gtet_mpi_result *res)
{
    int P = c->size;
    size_t nr = X->fr.n, mr = 0;
    const frec *frs = (const frec *)X->fr.p;
    gtet_status s = GTET_OK;
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    int *dst = mx_malloc((nr + 1) * sizeof *dst);
    frec *sb = mx_malloc((nr + 1) * sizeof *sb), *rb = NULL;
    size_t *perm = mx_malloc((nr + 1) * sizeof *perm), *ord = NULL;
    uint64_t *rep = NULL, *back = NULL;
    if (!scnt || !rcnt || !pos || !dst || !sb || !perm)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t i = 0; i < nr; i++)
        dst[i] = (int)(mx_mix64(frs[i].key[0] ^ mx_mix64(frs[i].key[1] ^ mx_mix64(frs[i].key[2]))) %
                       (uint64_t)P);
    mx_rank_order(dst, nr, P, scnt, pos, perm);
    for (size_t k = 0; k < nr; k++) sb[k] = frs[perm[k]];
    void *r;
    if ((s = mx_exchange(c, sb, scnt, sizeof(frec), &r, rcnt, &mr, 0)) != GTET_OK) goto done;
    rb = r;
    ord = mx_malloc((mr + 1) * sizeof *ord);
    rep = mx_malloc((mr + 1) * sizeof *rep);
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
    size_t tot;
    if ((s = mx_exchange(c, rep, rcnt, sizeof(uint64_t), &r, scnt, &tot, 0)) != GTET_OK)
        goto done;
    back = r;
    const uint64_t *sls = (const uint64_t *)X->slot.p;
    /* the hull facets: the slots left GTET_MPI_NO_TET, less those answered with a tet */
    uint64_t hull = nolid, ghull = 0;
    for (size_t k = 0; k < nr; k++) {
        if (res->neighbors32)   /* a tet id fits (ids32_fits) */
            res->neighbors32[sls[perm[k]]] =
                back[k] == GTET_MPI_NO_TET ? GTET_MPI_NO_TET32 : (uint32_t)back[k];
        else
            res->neighbors[sls[perm[k]]] = back[k];
        hull -= back[k] != GTET_MPI_NO_TET;
    }
    MPI_Allreduce(&hull, &ghull, 1, MPI_UINT64_T, MPI_SUM, c->comm);
    res->num_hull_facets = ghull;
done:
    free(scnt);
    free(rcnt);
    free(pos);
    free(dst);
    free(sb);
    free(rb);
    free(ord);
    free(perm);
    free(rep);
    free(back);
    return s;
}

/* the tile's vertices and the vertices the owned tets use (used[i]: local vertex i), listed by
 * vertex id.  Collective; the agreed status */
static gtet_status out_vertices(run *R, const uint8_t *usedv, gtet_mpi_result *res, lender *L)
{
    mctx *c = &R->c;
    size_t m = R->m;
    gtet_status s = GTET_OK;
    res->num_tile_vertices = m;
    res->tile_vertex_ids = mx_malloc((m + 1) * sizeof *res->tile_vertex_ids);
    res->tile_vertices = mx_malloc((3 * m + 1) * sizeof *res->tile_vertices);
    size_t w = 0;
    for (size_t i = 0; i < R->ns; i++) w += usedv[i];
    uint64_t *used = mx_malloc((w + 1) * sizeof *used);
    idpos *a = mx_malloc((w + 1) * sizeof *a), *b = mx_malloc((w + 1) * sizeof *b);
    res->used_vertices = mx_malloc((3 * w + 1) * sizeof *res->used_vertices);
    res->used_vertex_ids = used;
    res->num_used_vertices = w;
    if (!res->tile_vertex_ids || !res->tile_vertices || !used || !a || !b ||
        !res->used_vertices)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if (s == GTET_OK) {
        for (size_t i = 0; i < m; i++) {
            res->tile_vertex_ids[i] = R->sp[i].id;   /* S's first m points: the tile */
            memcpy(res->tile_vertices + 3 * i, R->sp[i].x, 3 * sizeof(double));
        }
        size_t k = 0;
        for (size_t i = 0; i < R->ns; i++)
            if (usedv[i]) {
                a[k].id = R->sp[i].id;
                a[k++].i = i;
            }
        if (sort_used(R, a, b, w, used, res->used_vertices) != 0)
            s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if (lend(L, a, (w + 1) * sizeof *a) != 0 || lend(L, b, (w + 1) * sizeof *b) != 0)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory (pages)");
    return mx_agree(c, s);
}

/* the 64-bit result over the local mesh's arrays (widen_one), before the matching allocates
 * anything that could take the memory an array without room grows into (can_grow); the vertex
 * ids (*vid) and the used marks lend their pages once the tets are widened.  The status */
static gtet_status widen_arrays(run *R, outx *X, uint64_t **vid, gtet_mpi_result *res,
                                size_t own, lender *L, uint64_t *nolid)
{
    mctx *c = &R->c;
    uint64_t unused;
    if (widen_one(&R->ptv, &res->tets, own, *vid, res->tet_offset, &unused) != 0)
        return mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    /* the vertex ids and the used marks are dead now: their pages go under the neighbours' */
    int bad = lend(L, *vid, (R->ns + 1) * sizeof **vid) != 0 || lend(L, X->used, R->ns + 1) != 0;
    *vid = NULL;
    X->used = NULL;
    if (bad) return mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory (pages)");
    if (widen_one(&R->ptn, &res->neighbors, own, NULL, res->tet_offset, nolid) != 0)
        return mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    return GTET_OK;
}

gtet_status mx_step_output(run *R, gtet_mpi_result *res)
{
    mctx *c = &R->c;
    int P = c->size, me = c->rank;
    gtet_status s = GTET_OK;
    size_t nt;
    release_rounds(R);
    take_local(R, &nt);
    mx_upper_clean();   /* E220 */
    uint32_t *tv = R->ptv, *nb = R->ptn;
    size_t m = R->m;
    outx X = {NULL, NULL, NULL, {NULL, 0, 0, sizeof(frec)}, {NULL, 0, 0, sizeof(uint64_t)}, 0, 0};
    lender L;
    lend_init(&L, R, 0);
    /* each local tet's index among the owned ones (NOLID: not owned); 4 B, as the neighbour
     * loop reads it at random */
    X.lid = mx_malloc((nt + 1) * sizeof *X.lid);
    /* the vertex ids of S in an array of their own: the tet loops read them at random, and
     * 8 B per vertex stays in cache where the 32 B records do not */
    uint64_t *vid = mx_malloc((R->ns + 1) * sizeof *vid);
    X.vid = vid;
    X.used = mx_calloc(R->ns + 1, 1);
    res->tet_offsets = mx_malloc(((size_t)P + 1) * sizeof *res->tet_offsets);
    if (!X.lid || !vid || !X.used || !res->tet_offsets)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    size_t own = 0;
    if (s == GTET_OK)
        for (size_t i = 0; i < R->ns; i++) vid[i] = R->sp[i].id;
    if (s == GTET_OK)
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *v = tv + 4 * t;
            if (t + OPF < nt) {
                const uint32_t *w = v + 4 * OPF;
                unsigned tw = (w[0] < m) + (w[1] < m) + (w[2] < m) + (w[3] < m);
                if (tw != 0 && tw != 4)
                    for (int i = 0; i < 4; i++) __builtin_prefetch(vid + w[i]);
            }
            /* owned: the smallest vertex is in this tile (D6); the vertex ids are read only for
             * a tet with vertices in and out of the tile (all in: owned; none: not), NOTES.md
             * E202 */
            unsigned tin = (v[0] < m) + (v[1] < m) + (v[2] < m) + (v[3] < m);
            int is_own = tin == 4;
            if (tin != 0 && tin != 4) {
                uint32_t lo = v[0];
                for (int i = 1; i < 4; i++)
                    if (vid[v[i]] < vid[lo]) lo = v[i];
                is_own = lo < m;
            }
            X.lid[t] = is_own ? (uint32_t)own++ : NOLID;
        }
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    uint64_t mine = own;
    MPI_Allgather(&mine, 1, MPI_UINT64_T, res->tet_offsets + 1, 1, MPI_UINT64_T, c->comm);
    res->tet_offsets[0] = 0;
    for (int q = 0; q < P; q++) res->tet_offsets[q + 1] += res->tet_offsets[q];
    res->tet_offset = res->tet_offsets[me];
    res->num_tets_global = res->tet_offsets[P];
    res->num_tets = own;
    /* 32 bits when asked for and every id fits (global figures: the same on every rank) */
    X.w32 = R->ids32 && ids32_fits(R->V, res->num_tets_global);
    res->id_bits = X.w32 ? 32 : 64;
    for (size_t t = 0; t < nt && s == GTET_OK; t++) {
        if (t + OPF < nt) {   /* row t + OPF is not compacted over yet (o <= t) */
            for (int f = 0; f < 4; f++) {
                uint32_t u = nb[4 * (t + OPF) + (size_t)f];
                if (u < nt) __builtin_prefetch(X.lid + u);
            }
            if (X.w32 && X.lid[t + OPF] != NOLID)   /* its vertex ids, read by compact_tet */
                for (int i = 0; i < 4; i++) __builtin_prefetch(vid + tv[4 * (t + OPF) + i]);
        }
        if (X.lid[t] != NOLID && compact_tet(R, &X, tv, nb, t, res->tet_offset) != 0)
            s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    }
    free(X.lid);
    X.lid = NULL;
    /* the vertices first: their arrays take the heap's free memory, and then S is dead: its
     * pages and the sort's lie under the result's room when it is widened (E221) */
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    lend_init(&L, R, own);
    L.on = L.on && !X.w32;   /* a 32-bit result needs no room */
    if ((s = out_vertices(R, X.used, res, &L)) != GTET_OK) goto done;
    if (lend(&L, R->sp, R->scap * sizeof *R->sp) != 0 || lend_free_memory(&L) != 0)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory (pages)");
    R->sp = NULL;
    R->scap = 0;
    uint64_t nolid = 0;
    if (s == GTET_OK && X.w32) {
        take_rows32(R, res, own);
        nolid = X.nolid;
    } else if (s == GTET_OK)
        s = widen_arrays(R, &X, &vid, res, own, &L, &nolid);
    lend_end(&L);
    if ((s = mx_agree(c, s)) == GTET_OK) s = match_facets(c, &X, nolid, res);
done:
    lend_end(&L);
    free(vid);
    free(X.lid);
    free(X.used);
    free(X.fr.p);
    free(X.slot.p);
    return s;
}
