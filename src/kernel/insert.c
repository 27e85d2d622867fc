/* insert.c -- Bowyer-Watson insertion of one point: location (locate.c), cavity, new tets,
 * adjacency.
 *
 * Why it is correct (the perturbed Delaunay tetrahedrization is unique and every sign used
 * here is exact or perturbed consistently, proofs/perturbation.md):
 *  - location: a tet in conflict with the point (locate.c, km_find_conflict).
 *  - cavity: the tets whose perturbed circumsphere contains the point (ghosts: the hull rule)
 *    form a connected, star-shaped region around it; a breadth-first search from the located
 *    tet collects them and the facets between a deleted and a kept tet (the boundary).
 *  - new tets: each boundary facet f of a deleted tet t gives the tet t with vertex f replaced
 *    by the point.  Star-shapedness keeps the orientation positive (ghosts included, in the
 *    lifted picture), and a ghost keeps its vertex at infinity in slot 3.
 *  - adjacency: two new tets are adjacent across the facet holding the point and a boundary
 *    edge; each boundary edge is shared by exactly two boundary facets, which traverse it in
 *    opposite directions (consistent orientation).  Directed edges are matched in a table
 *    indexed by cavity-local vertex ids (the paper's fast adjacency; adjacency_fast), or by a
 *    hash of the vertex pair for very large cavities (adjacency_hash).
 * No allocation in the loop except amortised growth of the per-thread buffers and the arrays.
 * The steps are in insert_steps.h, compiled here for x86-64's baseline and in insert_avx2.c
 * with AVX2; this file holds km_insert, which picks the instance (the filter's order, the CPU),
 * and the first tet.
 */
#include "insert_steps.h"

/* Move the rest of this thread's block of fresh slots to its free list, marked deleted so
 * that the compaction skips them. */
gtet_status km_flush_block(kctx *c)
{
    size_t left = c->blk_end - c->blk_next;
    if (left && grow((void **)&c->freelist, &c->free_cap, c->nfree + left, sizeof *c->freelist))
        return GTET_ERR_OUT_OF_MEMORY;
    for (size_t s = c->blk_next; s < c->blk_end; s++) {
        c->m->tv[4 * s] = KM_DEAD;
        c->freelist[c->nfree++] = (uint32_t)s;
    }
    c->blk_next = c->blk_end = 0;
    return GTET_OK;
}

/* conflict.h says what the sampler does and why */
__attribute__((cold, noinline)) void km_filter_order(kctx *c)
{
    const uint64_t calls = c->cnt.insphere_calls - c->sample_calls0;
    const uint64_t miss = c->static_misses;
    if (c->sampling == 1 && KM_ORDER_SHARE_LO_DEN * miss > KM_ORDER_SHARE_LO_NUM * calls) {
        /* the static test leaves more than a third: sample the level filter first */
        c->local_first = 1;
        c->sampling = 2;
        c->static_misses = 0;
        c->sample_calls0 = c->cnt.insphere_calls;
        c->order_left = KM_ORDER_SAMPLE;
    } else if (c->sampling) {  /* a sample ends: the order for the rest of the period */
        c->local_first = c->sampling == 2 &&
                        KM_ORDER_SHARE_HI_DEN * miss <= KM_ORDER_SHARE_HI_NUM * calls;
        c->order_left = KM_ORDER_PERIOD - KM_ORDER_SAMPLE * c->sampling;
        c->sampling = 0;
    } else {            /* a period ends: sample static-first */
        c->local_first = 0;
        c->sampling = 1;
        c->static_misses = 0;
        c->sample_calls0 = c->cnt.insphere_calls;
        c->order_left = KM_ORDER_SAMPLE;
    }
}

static __attribute__((noinline)) gtet_status km_insert_static_first(kctx *c, uint32_t pid,
                                                                    int *deferred)
{
    return km_insert_t(c, pid, deferred, 0);
}

static __attribute__((noinline)) gtet_status km_insert_local_first(kctx *c, uint32_t pid,
                                                                  int *deferred)
{
    return km_insert_t(c, pid, deferred, 1);
}

gtet_status km_insert(kctx *c, uint32_t pid, int *deferred)
{
    *deferred = 0;
    if (__builtin_expect(c->order_left-- == 0, 0)) km_filter_order(c);
#ifdef GTET_AVX2_TU
    if (c->avx2)
        return c->local_first ? km_insert_local_first_avx2(c, pid, deferred)
                             : km_insert_static_first_avx2(c, pid, deferred);
#endif
    return c->local_first ? km_insert_local_first(c, pid, deferred)
                         : km_insert_static_first(c, pid, deferred);
}

gtet_status km_first_tet(kctx *c, uint32_t a, uint32_t b, uint32_t cc, uint32_t d)
{
    kmesh *m = c->m;
    gtet_status s = km_reserve(m, 5);
    if (s != GTET_OK) return s;
    int o = pred_orient3d(km_pt(m, a), km_pt(m, b), km_pt(m, cc), km_pt(m, d), &c->cnt);
    if (o == 0) return GTET_ERR_INTERNAL;
    if (o < 0) {
        uint32_t tmp = b;
        b = cc;
        cc = tmp;
    }
    const uint32_t v[4] = {a, b, cc, d};
    m->nt = 5;
    memcpy(m->tv, v, sizeof v);
    /* ghost g = 1+k across facet k: the facet's vertices in increasing slot order x<y<z,
     * orient3d(x,y,z,v_k) has the sign (-1)^(3-k); it must be negative, so swap y and z when
     * 3-k is even. */
    for (int k = 0; k < 4; k++) {
        uint32_t g = (uint32_t)(1 + k), w[3];
        int n = 0;
        for (int j = 0; j < 4; j++)
            if (j != k) w[n++] = v[j];
        if (((3 - k) & 1) == 0) {
            uint32_t tmp = w[1];
            w[1] = w[2];
            w[2] = tmp;
        }
        uint32_t *gv = m->tv + 4 * (size_t)g;
        gv[0] = w[0];
        gv[1] = w[1];
        gv[2] = w[2];
        gv[3] = KM_GHOST;
        m->tn[4 * g + 3] = (uint32_t)k;     /* tet 0, facet k */
        m->tn[k] = 4 * g + 3;
    }
    /* ghost-ghost adjacency: ghost facet i < 3 holds G and the edge of its finite facet
     * without vertex i; the other ghost holding the same edge is its neighbour. */
    for (uint32_t g = 1; g <= 4; g++)
        for (int i = 0; i < 3; i++) {
            const uint32_t *gv = m->tv + 4 * (size_t)g;
            uint32_t e0 = gv[(i + 1) % 3], e1 = gv[(i + 2) % 3];
            for (uint32_t h = 1; h <= 4; h++) {
                if (h == g) continue;
                const uint32_t *hv = m->tv + 4 * (size_t)h;
                for (int j = 0; j < 3; j++) {
                    uint32_t f0 = hv[(j + 1) % 3], f1 = hv[(j + 2) % 3];
                    if ((f0 == e0 && f1 == e1) || (f0 == e1 && f1 == e0))
                        m->tn[4 * g + (uint32_t)i] = 4 * h + (uint32_t)j;
                }
            }
        }
    for (uint32_t h = 0; GTET_DEBUG_ON && h < 20; h++) GTET_DEBUG_ASSERT(m->tn[m->tn[h]] == h);
    c->last = 0;
    return GTET_OK;
}
