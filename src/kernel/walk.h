/* walk.h -- the visibility walk (locate.c's header says why it finds a tet in conflict) and
 * the location step km_insert starts with (km_find_conflict), as static functions: included by
 * locate.c (km_locate), and by insert_steps.h, so that each instance of km_insert (insert.c
 * for x86-64's baseline, insert_avx2.c with AVX2) has its own copy.  With AVX2 a step tests
 * the tet's four facets at once (filter_packed.h pred_orient3d_facets4_: the scalar filter's
 * answers, lane by lane) and picks, without a branch a facet, the facet the scalar walk would
 * cross: the first, in the step's random order, whose orient3d is negative.  The same tets are
 * visited, the same random numbers drawn and the same calls counted either way: the walk ends
 * where it did, and the mesh's arrays are the same bit for bit (NOTES.md E173). */
#ifndef GTET_KERNEL_WALK_H
#define GTET_KERNEL_WALK_H
#include "conflict.h"

static inline uint32_t rng_next(kctx *c)
{
    c->rng = c->rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(c->rng >> 33);
}

/* orient3d of tet t with its vertex f replaced by p (t finite); the filter's answer when it
 * decides (filter_known), else the exact rest's. */
static inline int orient_replaced(kctx *c, uint32_t t, int f, const double *p, int filter_known,
                                  int filter)
{
    const kmesh *m = c->m;
    const uint32_t *v = m->tv + 4 * (size_t)t;
    const double *q[4];
    for (int i = 0; i < 4; i++) q[i] = km_pt(m, v[i]);
    q[f] = p;
    c->cnt.orient_calls++;
    int s = filter_known ? filter : pred_orient3d_filter(q[0], q[1], q[2], q[3], m->ps.o3_seps);
    return s ? s : pred_orient3d_rest(q[0], q[1], q[2], q[3], &m->ps, &c->cnt);
}

/* The facet of finite tet t to cross towards p: the first of `untested` (bit k: facet
 * (r + k) & 3) whose orient3d with p in its slot is negative, or -1 (t contains p in its
 * closure).  Counts one orient3d call a facet tested, as the scalar loop does.  Inlined
 * always: as a call of its own (gcc's choice) it saved and restored six registers and
 * realigned the stack at every step (NOTES.md E248). */
static inline __attribute__((always_inline)) int walk_facet(kctx *c, uint32_t t, const double *p,
                                                          uint32_t r, uint32_t untested,
                                                          int *strict)
{
    *strict = 0;
#ifdef PRED_ORIENT3D_FACETS4
    const kmesh *m = c->m;
    const uint32_t *v = m->tv + 4 * (size_t)t;
    unsigned neg, und;
    pred_orient3d_facets4_(km_pt(m, v[0]), km_pt(m, v[1]), km_pt(m, v[2]), km_pt(m, v[3]), p,
                           m->ps.o3_seps, &neg, &und);
    /* the masks in the step's order: bit k for facet (r + k) & 3 */
    const unsigned rr = r & 3;
    neg = ((neg >> rr) | (neg << (4 - rr))) & untested;
    und = ((und >> rr) | (und << (4 - rr))) & untested;
    if (__builtin_expect(und == 0, 1)) {
        if (!neg) {
            c->cnt.orient_calls += (uint64_t)__builtin_popcount(untested);
            *strict = 1;  /* every facet tested decided positive by the filter: not zero */
            return -1;
        }
        const unsigned k = (unsigned)__builtin_ctz(neg);
        c->cnt.orient_calls += (uint64_t)__builtin_popcount(untested & ((2u << k) - 1));
        return (int)((r + k) & 3);
    }
    /* a facet the filter leaves: the scalar loop, with the lanes' answers where they decide */
    for (; untested; untested &= untested - 1) {
        const unsigned k = (unsigned)__builtin_ctz(untested);
        const int f = (int)((r + k) & 3);
        if (orient_replaced(c, t, f, p, !(und >> k & 1), (neg >> k & 1) ? -1 : 1) < 0) return f;
    }
    return -1;
#else
    for (; untested; untested &= untested - 1) {
        const int f = (int)((r + (uint32_t)__builtin_ctz(untested)) & 3);
        if (orient_replaced(c, t, f, p, 0, 0) < 0) return f;
    }
    return -1;
#endif
}

/* Visibility walk from c->last to a tet in conflict with p.  In a parallel pass it never
 * enters a tet that is not this thread's (km_owned; *found = UINT32_MAX: defer), and it gives
 * up instead of scanning when the step budget runs out (a scan would read other threads'
 * tets); so does it when may_scan is 0 (km_locate). */
static __attribute__((noinline, unused)) gtet_status km_walk_t(kctx *c, const double *p,
                                                               uint32_t *found, int may_scan)
{
    const kmesh *m = c->m;
    uint32_t t = c->last;
    uint32_t entry = UINT32_MAX;   /* handle 4t+f of the facet we came in through */
    if (km_is_ghost(m, t)) {
        /* start from the ghost's finite neighbour and test all four of its facets: p may be
         * beyond the hull facet too (then the walk steps back into this ghost, entered
         * through its finite facet with p strictly beyond, which conflicts).  Skipping that
         * facet as if it had been crossed located a tet p is not in when p is outside the
         * hull (sphere points in a parallel pass: "internal error"; serially a linear scan). */
        t = m->tn[4 * (size_t)t + 3] >> 2;
    }
    /* m->nt is bumped by other threads' atomic captures (ensure_room) during a parallel
     * pass: read it atomically too (a plain read would be a data race; ThreadSanitizer). */
    size_t nt_now;
#pragma omp atomic read
    nt_now = m->nt;
    uint64_t budget = 64 + 4 * (uint64_t)nt_now;
    for (uint64_t step = 0; step < budget; step++) {
        if (km_is_ghost(m, t)) {  /* entered through its finite facet, strictly beyond */
            *found = t;
            c->walk_steps += step;
            return GTET_OK;
        }
        const uint32_t r = rng_next(c);
        /* the facets to test, the one entered through left out, in the order r + 0..3 (bit k
         * of `untested` is facet (r + k) & 3): a mask rather than a test of each facet against
         * the entry, a branch taken once in four at random (NOTES.md E167); at the start
         * entry is UINT32_MAX, and entry >> 2 is no slot (KM_MAX_SLOTS) */
        const uint32_t skip = entry >> 2 == t ? 1u << (((entry & 3) - r) & 3) : 0;
        int strict;
        const int f = walk_facet(c, t, p, r, 15u & ~skip, &strict);
        if (f < 0) {
            *found = t;
            c->walk_inside = (uint8_t)strict;
            c->walk_steps += step;
            return GTET_OK;
        }
        const uint32_t h = m->tn[4 * (size_t)t + (size_t)f];
        if (c->colour && !km_owned(c, h >> 2)) {
            *found = UINT32_MAX;
            c->walk_steps += step;
            return GTET_OK;
        }
        entry = h;
        t = h >> 2;
    }
    c->walk_steps += budget;
    if (c->colour || !may_scan) {
        *found = UINT32_MAX;
        return GTET_OK;
    }
    return km_scan_for_conflict(c, p, found);
}

/* A tet in conflict with p (*t0): over the hull first when the last insertion was outside it,
 * else by the visibility walk from c->last; *t0 = UINT32_MAX in a parallel pass
 * when the walk met a tet not this thread's or ran out of steps (defer).  Inlined into
 * km_insert (one call a point less), always: as a function shared by the two orders' instances
 * its filter order became a test per call (u1M +2 %: NOTES.md E188); local_first as for
 * km_conflicts_in. */
__attribute__((always_inline)) static inline gtet_status km_find_conflict(kctx *c,
                                                                          const double *p,
                                                                          uint32_t *t0,
                                                                          const int local_first)
{
    if (__builtin_expect(c->last_ghost != UINT32_MAX, 0)) {
        *t0 = km_hull_search(c, p);
        c->last_ghost = UINT32_MAX;
        if (*t0 != UINT32_MAX) return GTET_OK;
    }
    c->walk_inside = 0;
    gtet_status s = km_walk_t(c, p, t0, 1);
    if (s != GTET_OK || *t0 == UINT32_MAX) return s;
    /* a finite tet with p strictly inside conflicts: its interior lies in the open
     * circumball, so the insphere determinant is not zero and positive (NOTES.md E249) */
    if (c->walk_inside ||
        km_conflicts_in(c, c->m->tv, c->m->v, c->m->ps.is_seps, local_first, *t0, p))
        return GTET_OK;
    /* the located tet must conflict (locate.c) */
    if (c->colour) return GTET_ERR_INTERNAL;
    return km_scan_for_conflict(c, p, t0);
}
#endif
