/* insert_steps.h -- the steps of one insertion (insert.c's header says why they are correct):
 * the cavity search, the new tets and their adjacency, as static functions and the template
 * km_insert_t.  Included by insert.c, compiled for x86-64's baseline, and by insert_avx2.c,
 * the same text compiled with AVX2 enabled, where the insphere filter takes four lanes at a
 * time (filter_packed.h pred_insphere_lanes4_; NOTES.md E171).  Nothing here may depend on
 * which. */
#ifndef GTET_KERNEL_INSERT_STEPS_H
#define GTET_KERNEL_INSERT_STEPS_H
#include "walk.h"

#include "../base/base.h"

#include <stdlib.h>
#include <string.h>

static int grow(void **buf, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return 0;
    size_t nc = *cap ? *cap : 64;
    while (nc < need) nc *= 2;
    void *b = realloc(*buf, nc * elem);
    if (!b) return -1;
    *buf = b;
    *cap = nc;
    return 0;
}

/* The cavity search will read the records of t's neighbours: start loading them now, while
 * the tets queued before t are processed (a hint only; dig calls it on t0 and, from then on,
 * on the tet KM_PREFETCH_AHEAD places after the one it searches).  With it the two arrays are
 * as fast as one 32-byte record per tet holding vertices and neighbours together (one line per
 * tet instead of two), and their compaction allocates nothing (NOTES.md D2). */
static inline void prefetch_neighbours(const kmesh *m, uint32_t t)
{
    const uint32_t *n = m->tn + 4 * (size_t)t;
    for (int f = 0; f < 4; f++) {
        /* its vertices for the conflict test, its neighbours for the search when it joins the
         * cavity (this function on it) or for fill's back link when it stays outside: the
         * load of its tn line after the kill was the search's largest stall on the scans
         * (NOTES.md E175) */
        __builtin_prefetch(m->tv + 4 * (size_t)(n[f] >> 2));
        __builtin_prefetch(m->tn + 4 * (size_t)(n[f] >> 2));
    }
}

/* Make sure `need` slots can be taken without failing: serially by growing the arrays, in a
 * parallel pass by claiming blocks of fresh slots from the shared counter (the arrays never
 * grow during a pass; GTET_ERR_TOO_LARGE then means "no room in this pass").  Inlined in
 * both instances of km_insert, as it was in the one before them. */
static inline __attribute__((always_inline)) gtet_status ensure_room(kctx *c, size_t need)
{
    kmesh *m = c->m;
    if (!c->colour) {
        if (c->nfree >= need) return GTET_OK;
        return km_reserve(m, m->nt + (need - c->nfree));
    }
    while (c->nfree + (c->blk_end - c->blk_next) < need) {
        gtet_status s = km_flush_block(c);
        if (s != GTET_OK) return s;
        size_t start;
#pragma omp atomic capture
        { start = m->nt; m->nt += KM_SLOT_BLOCK; }
        if (start >= m->cap) return GTET_ERR_TOO_LARGE;
        c->blk_next = start;
        c->blk_end = start + KM_SLOT_BLOCK < m->cap ? start + KM_SLOT_BLOCK : m->cap;
    }
    return GTET_OK;
}

/* Take one slot; ensure_room() said there is one. */
static inline uint32_t take_slot(kctx *c)
{
    if (c->nfree) return c->freelist[--c->nfree];
    if (c->colour) return (uint32_t)c->blk_next++;
    return (uint32_t)c->m->nt++;
}

/* The new tets and their adjacency.  New tet i is boundary record i with the point in slot
 * f; it is glued to the outer facet at once.  Its three facets holding the point are linked
 * through the edge table, the paper's fast adjacency in HXT's branch-free form: write the
 * boundary triangle of tet i as T = (t0, t1, t2), the slots other than f in the cyclic order
 * TRI[f] for which (t0, t1, t2, f) is an even permutation of (0, 1, 2, 3).  Every new tet is
 * positively oriented in the mesh's combinatorial orientation (ghosts included), and two
 * consistently oriented tets induce opposite orientations on the facet they share, so the
 * new tets across the edge t1 -> t2 of one triangle holds it as t2 -> t1 (the cavity
 * boundary is a closed, consistently oriented surface).  Scatter: the facet opposite slot t0
 * (which holds the point and the edge t1 -> t2) is stored at table[t1][t2], in cavity-local
 * ids; gather: its neighbour is table[t2][t1].  Every directed edge of the boundary is written
 * exactly once before the gather reads its reverse, so the table never needs clearing (each
 * entry is stamped with the cavity's number, and the gather checks the stamps).
 * Local ids: 0 for the vertex at infinity, 1.. for the finite boundary vertices in order of
 * first sight (vloc, 0xff outside a cavity, reset at the end; in a parallel pass a vertex of
 * another colour -- a cavity tet may have one, `foreign` -- is looked up in a local list
 * instead, as another thread may be using its vloc: O9).  A closed boundary with nb
 * triangles has nb/2 + 2 vertices (Euler), so nb <= KM_FAST_FACETS fits the 64 ids; the id
 * count is checked anyway (a non-closed boundary would be an internal error, not an overflow).
 * Returns 1 when done, 0 when the hash path must do it (nothing linked), -1 when a stamp is
 * stale (an internal error). */
static const uint8_t TRI[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
#define KM_FAST_FACETS (2 * (KM_LOC_MAX - 3))

static inline void clear_vloc(uint8_t *vloc, const uint32_t *seen, int foreign, unsigned nseen,
                              unsigned next)
{
    if (foreign)
        for (unsigned q = 0; q < nseen; q++) vloc[seen[q]] = 0xff;
    else
        for (unsigned l = 1; l < next; l++) vloc[seen[l]] = 0xff;
}

/* Instantiated twice (foreign = 0 / 1, a constant): the common case stays branch-free. */
static inline __attribute__((always_inline)) int adjacency_fast_t(kctx *c, const uint32_t *slots,
                                                                  size_t nb, const int foreign)
{
    if (nb > KM_FAST_FACETS) return 0;
    /* entries carry this cavity's number in their high half: an entry the gather reads must
     * have been written by this cavity (a stale one means the boundary was not a closed,
     * consistently oriented surface: an internal error, never a silently wrong link) */
    const uint64_t gen = (uint64_t)(++c->cavity_gen) << 32;
    kmesh *m = c->m;
    uint8_t *vloc = m->vloc;
    uint64_t *tab = c->table;
    uint32_t *tn = m->tn;
    const kbound *b = c->bnd;
    uint32_t seen[KM_LOC_MAX + 3];    /* the vertices whose vloc is set */
    uint32_t fv[KM_LOC_MAX + 3];      /* foreign vertices (other colour) and their ids */
    uint8_t fl[KM_LOC_MAX + 3];
    unsigned nseen = 0, nf = 0;
    uint8_t loc[3 * KM_FAST_FACETS];
    unsigned next = 1;
    for (size_t i = 0; i < nb; i++) {
        const uint8_t *T = TRI[b[i].f];
        for (int j = 0; j < 3; j++) {
            const uint32_t v = b[i].v[T[j]];
            unsigned l = 0;
            if (v != KM_GHOST) {
                if (foreign && c->colour[v] != c->mine) {
                    /* another thread may use vloc[v] right now (O9): a local list instead */
                    unsigned q = 0;
                    while (q < nf && fv[q] != v) q++;
                    if (q == nf) {
                        fv[nf] = v;
                        fl[nf++] = (uint8_t)next++;
                    }
                    l = fl[q];
                } else {
                    l = vloc[v];
                    const unsigned fresh = l == 0xff;
                    l = fresh ? next : l;
                    vloc[v] = (uint8_t)l;
                    if (foreign) {  /* ids and vloc entries differ: count the latter */
                        seen[nseen] = v;
                        nseen += fresh;
                    } else {
                        seen[next] = v;  /* id l's vertex */
                    }
                    next += fresh;
                }
            }
            loc[3 * i + (size_t)j] = (uint8_t)l;
        }
        if (next > KM_LOC_MAX) {  /* cannot happen for a closed boundary: give up */
            clear_vloc(vloc, seen, foreign, nseen, next);
            return 0;
        }
        const unsigned l0 = loc[3 * i], l1 = loc[3 * i + 1], l2 = loc[3 * i + 2];
        const uint64_t h = gen | (4 * slots[i]);
        tab[l1 * KM_LOC_MAX + l2] = h + T[0];
        tab[l2 * KM_LOC_MAX + l0] = h + T[1];
        tab[l0 * KM_LOC_MAX + l1] = h + T[2];
    }
    uint64_t stale = 0;
    for (size_t i = 0; i < nb; i++) {
        const uint8_t *T = TRI[b[i].f];
        const unsigned l0 = loc[3 * i], l1 = loc[3 * i + 1], l2 = loc[3 * i + 2];
        const uint32_t h = 4 * slots[i];
        const uint64_t e0 = tab[l2 * KM_LOC_MAX + l1], e1 = tab[l0 * KM_LOC_MAX + l2];
        const uint64_t e2 = tab[l1 * KM_LOC_MAX + l0];
        stale |= (e0 ^ gen) >> 32 | (e1 ^ gen) >> 32 | (e2 ^ gen) >> 32;
        tn[h + T[0]] = (uint32_t)e0;
        tn[h + T[1]] = (uint32_t)e1;
        tn[h + T[2]] = (uint32_t)e2;
    }
    clear_vloc(vloc, seen, foreign, nseen, next);
    return stale ? -1 : 1;
}

static __attribute__((noinline)) int adjacency_fast(kctx *c, const uint32_t *slots, size_t nb)
{
    return adjacency_fast_t(c, slots, nb, 0);
}

static __attribute__((noinline)) int adjacency_fast_foreign(kctx *c, const uint32_t *slots,
                                                            size_t nb)
{
    return adjacency_fast_t(c, slots, nb, 1);
}

/* Fallback for large cavities: open addressing on the (min, max) vertex pair. */
static gtet_status adjacency_hash(kctx *c, const uint32_t *slots, size_t nb)
{
    kmesh *m = c->m;
    const kbound *b = c->bnd;
    size_t need = 16;
    while (need < 4 * 3 * nb) need <<= 1;
    size_t cap = need, mask = cap - 1;
    /* entry i: the edge key in htab[2i], the waiting facet handle in htab[2i+1] */
    if (grow((void **)&c->htab, &c->htab_cap, 2 * cap, sizeof *c->htab))
        return GTET_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < 2 * cap; i++) c->htab[i] = UINT64_MAX;
    int pending = 0;
    for (size_t i = 0; i < nb; i++) {
        int f = (int)b[i].f;
        for (int k = 0; k < 4; k++) {
            if (k == f) continue;
            int i1 = -1, i2 = -1;
            for (int j = 0; j < 4; j++)
                if (j != f && j != k) {
                    if (i1 < 0) i1 = j; else i2 = j;
                }
            uint64_t va = b[i].v[i1], vb = b[i].v[i2];
            uint64_t key = va < vb ? (va << 32 | vb) : (vb << 32 | va);
            size_t h = (size_t)((key * 0x9e3779b97f4a7c15ULL) >> 20) & mask;
            uint32_t handle = 4 * slots[i] + (uint32_t)k;
            for (;;) {
                if (c->htab[2 * h] == UINT64_MAX) {
                    c->htab[2 * h] = key;
                    c->htab[2 * h + 1] = handle;
                    pending++;
                    break;
                }
                if (c->htab[2 * h] == key && c->htab[2 * h + 1] != UINT64_MAX) {
                    uint32_t other = (uint32_t)c->htab[2 * h + 1];
                    m->tn[other] = handle;
                    m->tn[handle] = other;
                    c->htab[2 * h + 1] = UINT64_MAX;  /* consumed; key stays as a tombstone */
                    pending--;
                    break;
                }
                h = (h + 1) & mask;
            }
        }
    }
    c->big_cavities++;
    return pending == 0 ? GTET_OK : GTET_ERR_INTERNAL;
}

/* Undo the DELETED marks of an abandoned cavity: nothing else was written. */
static void rollback(kctx *c, size_t ncav)
{
    for (size_t i = 0; i < ncav; i++) km_revive(c->m, c->cav[i]);
    c->conflicts++;
}

/* km_insert's three steps.  Each is inlined into it (one function in the object code, as the
 * hot loop was written); a parallel pass defers through *deferred, with nothing written. */
#define KM_STEP static inline __attribute__((always_inline))

/* dig: the cavity, a breadth-first search over the tets in conflict with p from t0: the
 * deleted tets in c->cav[0..*ncav) (marked dead), the boundary facets in c->bnd[0..*nb) as
 * the new tets they become.  In a parallel pass every tet is checked to be this thread's
 * before it is marked (O2); a tet that is not rolls the marks back and defers.  *foreign: a
 * cavity tet has a vertex of another colour (own_min 3).  local_first: the insphere filter's
 * order (km_filter_order), a constant in each of its instances.
 *
 * The answer of each conflict test is data, not a branch (NOTES.md E252): it is a branch
 * taken about half the time at random, and each miss threw away the work begun after it
 * while the test's long chain of products resolved it.  Both outcomes are written, and the
 * counts advance by the answer: u is appended to the cavity list (ncav += in), the boundary
 * record of t's facet f is written at nb (nb += 1 - in), u's first vertex word gets the mark
 * or keeps its value (| in << 31).  A slot written past a count is rewritten by the next
 * test or never read, and the room for the four facets of t is checked before them.  The
 * mark's store when u does not conflict writes the value already there; in a parallel pass
 * it is made only to a tet this thread owns, which no other thread reads or writes during
 * the pass (proofs/parallel.md C1, C3); a conflicting tet it does not own defers, as before.
 * Ownership is asked of every tested tet there, so it is asked cheaply: with own_min 4 the
 * popped tet's vertices all have the thread's colour, and u, which shares three of them, is
 * the thread's exactly when its fourth vertex has it too or is the vertex at infinity
 * (km_owned's rule, one colour read); with own_min 3, km_owned_bits.
 * The kept cache takes u either way: a killed u is dead, so no later facet tests it. */
#define KM_KEPT_CACHE 64
/* The cavity tet whose neighbours' lines are fetched while tet i is searched: i + AHEAD
 * (a prefetch at each kill made the answer a branch again; NOTES.md E252) */
#define KM_PREFETCH_AHEAD 2
KM_STEP gtet_status dig(kctx *c, uint32_t pid, const double *p, uint32_t t0, size_t *ncav_out,
                        size_t *nb_out, int *foreign_out, int *deferred, const int local_first,
                        const int par)
{
    kmesh *m = c->m;
    size_t ncav = 0, nb = 0;
    if (grow((void **)&c->cav, &c->cav_cap, 64, sizeof *c->cav)) return GTET_ERR_OUT_OF_MEMORY;
    /* the walk only enters, and starts from, tets of this thread (parallel pass); checked
     * again before the first write (O2) */
    unsigned foreign = 0;
    if (par) {
        const int own = km_owned(c, t0);
        if (!own) {
            c->conflicts++;
            *deferred = 1;
            return GTET_OK;
        }
        foreign = own == 2;
    }
    c->cav[ncav++] = t0;
    km_kill(m, t0);
    prefetch_neighbours(m, t0);
    /* tets of this cavity's boundary already tested (kept), direct-mapped on the slot's low
     * bits: a kept tet next to two deleted ones is not tested twice (NOTES.md Q6, E61) */
    uint32_t kept[KM_KEPT_CACHE];
    memset(kept, 0xff, sizeof kept);
    /* read once a point (the arrays move only when fill grows them; NOTES.md E142) */
    uint32_t *const tv = m->tv;
    const uint32_t *const tn = m->tn;
    const double *const V = m->v;
    const double seps = m->ps.is_seps;
    /* and the ownership's (a call the filter's rest makes could change them, for the
     * compiler, which then read them at every test) */
    const uint8_t *const col = c->colour;
    const uint8_t mine = c->mine;
    const int own4 = c->own_min == 4;
    for (size_t i = 0; i < ncav; i++) {
        const uint32_t t = c->cav[i];
        /* (the last one again near the end of the list: a branch there was mispredicted
         * once a point or so) */
        const size_t ahead = i + KM_PREFETCH_AHEAD;
        prefetch_neighbours(m, c->cav[ahead < ncav ? ahead : ncav - 1]);
        /* room for what t's four facets can add, checked once a tet rather than once a push;
         * and t's vertices, which every boundary record of t copies, read once (t is already
         * marked: its mark cleared in the copy) */
        if (grow((void **)&c->cav, &c->cav_cap, ncav + 4, sizeof *c->cav) ||
            grow((void **)&c->bnd, &c->bnd_cap, nb + 4, sizeof *c->bnd)) {
            rollback(c, ncav);
            return GTET_ERR_OUT_OF_MEMORY;
        }
        uint32_t tvt[4];
        memcpy(tvt, tv + 4 * (size_t)t, sizeof tvt);
        tvt[0] &= ~KM_DEAD;
        const uint32_t tghost = tvt[3] == KM_GHOST;
        /* the facets whose neighbour is live, as a mask read before any test: the loop
         * below visits them in the same order as a test of each in turn would (a kill in it
         * is of a neighbour of t, which no other facet of t has), and it does not branch on
         * each neighbour's mark, a branch as often taken as not (NOTES.md E167) */
        uint32_t hn[4];
        unsigned live = 0;
        for (uint32_t f = 0; f < 4; f++) {
            hn[f] = tn[4 * (size_t)t + f];
            live |= (unsigned)((tv[4 * (size_t)(hn[f] >> 2)] & KM_DEAD) == 0) << f;
            /* and the coordinates of the neighbour's vertex across facet f, the one vertex
             * of its conflict test not in t (NOTES.md E247).  A hint, its address computed
             * as an integer: a ghost's apex (KM_GHOST) and a dead tet's marked vertex 0 point
             * outside V, where a prefetch is dropped without a fault (clearing the mark first
             * measured slower). */
            __builtin_prefetch((const void *)((uintptr_t)V + 3 * sizeof *V * (uintptr_t)tv[hn[f]]));
        }
        for (; live; live &= live - 1) {
            const uint32_t f = (uint32_t)__builtin_ctz(live);
            const uint32_t h = hn[f];
            const uint32_t u = h >> 2;
            uint32_t *k = &kept[u & (KM_KEPT_CACHE - 1)];
            const uint32_t in = *k != u ? km_conflict_bit(c, tv, V, seps, local_first, u, p) : 0u;
            if (par) {
                unsigned own;  /* km_owned(c, u) != 0, as the comment above says */
                if (__builtin_expect(own4, 1)) {
                    const uint32_t apex = tv[h];
                    const unsigned inf = apex == KM_GHOST;
                    own = inf | (col[inf ? 0 : apex] == mine);
                } else {
                    const int o = km_owned_bits(c, u);
                    own = o != 0;
                    foreign |= in & (o == 2);
                }
                GTET_DEBUG_ASSERT(own == (km_owned(c, u) != 0));  /* the shortcut is km_owned */
                if (__builtin_expect(own, 1)) {
                    tv[4 * (size_t)u] |= in << 31;  /* ours: nobody else's to read (C3) */
                } else if (in) {                    /* in conflict and not ours: defer */
                    rollback(c, ncav);
                    *deferred = 1;
                    return GTET_OK;
                }
            } else {
                tv[4 * (size_t)u] |= in << 31;
            }
            c->cav[ncav] = u;
            ncav += in;
            *k = u;
            kbound *b = &c->bnd[nb];
            nb += 1u - in;
            memcpy(b->v, tvt, sizeof b->v);
            b->v[f] = pid;
            b->outer = h;
            b->f = f;
            /* A ghost whose finite facet is on the boundary becomes a finite tet (a,b,c,p).
             * The consistency of the hull rule with the interior rule (proofs/perturbation.md)
             * makes it positively oriented; a flat or inverted tet would be a predicate bug,
             * so it is checked (only for points outside the current hull).  One branch, rarely
             * taken: `f == 3` alone is a branch taken about once in four, at random (NOTES.md
             * E167). */
            if (__builtin_expect(((1u - in) & (uint32_t)(f == 3) & tghost) != 0, 0) &&
                pred_orient3d(km_pt(m, tvt[0]), km_pt(m, tvt[1]), km_pt(m, tvt[2]), p,
                              &c->cnt) <= 0) {
                rollback(c, ncav);
                return GTET_ERR_INTERNAL;
            }
        }
    }
    *ncav_out = ncav;
    *nb_out = nb;
    *foreign_out = (int)foreign;
    return GTET_OK;
}

/* The back links of the new tets in slots[0..nb), and that they are this thread's (every new
 * tet keeps at least the owned vertices of the deleted tet its facet came from, and p is of
 * the thread's colour).  Debug builds only. */
static void check_new_tets(const kctx *c, const uint32_t *slots, size_t nb)
{
    const uint32_t *tn = c->m->tn;
    for (size_t i = 0; i < nb; i++) {
        GTET_DEBUG_ASSERT(!c->colour || km_owned(c, slots[i]));
        for (uint32_t f = 0; f < 4; f++) {
            const uint32_t h = 4 * slots[i] + f;
            GTET_DEBUG_ASSERT(tn[tn[h]] == h);
        }
    }
}

/* fill: the cavity's nb new tets in slots (the cavity's own first, then the free list, then
 * fresh ones), glued to the outer facets and linked to each other; the next walk starts from
 * a finite new tet when there is one.  Defers (parallel pass) when no slot is left. */
KM_STEP gtet_status fill(kctx *c, size_t ncav, size_t nb, int foreign, int *deferred)
{
    kmesh *m = c->m;
    if (grow((void **)&c->freelist, &c->free_cap, c->nfree + ncav, sizeof *c->freelist)) {
        rollback(c, ncav);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    const size_t need = nb > ncav ? nb - ncav : 0;
    gtet_status s = ensure_room(c, need);
    if (s != GTET_OK) {
        rollback(c, ncav);
        if (c->colour && s == GTET_ERR_TOO_LARGE) {  /* no room left in this pass */
            c->out_of_room = 1;
            *deferred = 1;
            return GTET_OK;
        }
        return s;
    }
    GTET_DEBUG_ASSERT(c->nfree + (c->colour ? c->blk_end - c->blk_next : m->cap - m->nt) >= need);
    if (grow((void **)&c->freelist, &c->free_cap, c->nfree + ncav, sizeof *c->freelist) ||
        grow((void **)&c->cav, &c->cav_cap, nb, sizeof *c->cav)) {
        rollback(c, ncav);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    /* The new tets take the cavity's own slots first, in the cavity's order, then the free
     * list's from its top, then fresh ones.  The slots array is the cavity buffer, whose first
     * min(nb, ncav) entries are those slots already; what the cavity leaves over goes to the
     * free list with cav[nb] on top.  (The same slots, in the same order, as pushing the whole
     * cavity in reverse and popping nb: two loops of ncav less a point; NOTES.md E253.) */
    uint32_t *slots = c->cav;
    if (nb <= ncav)
        for (size_t i = ncav; i-- > nb;) c->freelist[c->nfree++] = c->cav[i];
    else
        for (size_t i = ncav; i < nb; i++) slots[i] = take_slot(c);
    for (size_t i = 0; i < nb; i++) {
        const kbound *b = &c->bnd[i];
        uint32_t n = slots[i];
        memcpy(m->tv + 4 * (size_t)n, b->v, sizeof b->v);
        m->tn[4 * (size_t)n + b->f] = b->outer;
        m->tn[b->outer] = 4 * n + b->f;
    }
    const int fast = foreign ? adjacency_fast_foreign(c, slots, nb) : adjacency_fast(c, slots, nb);
    if (fast < 0) return GTET_ERR_INTERNAL;
    if (fast == 0) {
        s = adjacency_hash(c, slots, nb);
        if (s != GTET_OK) return s;
    }
    if (GTET_DEBUG_ON) check_new_tets(c, slots, nb);
    c->tets_created += nb;
    c->last = slots[0];
    for (size_t i = 0; i < nb; i++)
        if (m->tv[4 * (size_t)slots[i] + 3] != KM_GHOST) {
            c->last = slots[i];
            break;
        }
    return GTET_OK;
}

/* p, inserted from outside the hull, is a hull vertex now: one of its new ghosts (c->cav
 * holds the new tets' slots after fill) starts the next hull search (E32). */
static __attribute__((noinline)) void remember_ghost(kctx *c, size_t nb)
{
    for (size_t i = 0; i < nb; i++)
        if (km_is_ghost(c->m, c->cav[i])) {
            c->last_ghost = c->cav[i];
            return;
        }
}

/* km_insert with the filter's order a constant: two instances, so that each keeps the code
 * (and the registers) of one order only */
static inline __attribute__((always_inline)) gtet_status km_insert_t(kctx *c, uint32_t pid,
                                                                     int *deferred,
                                                                     const int local_first)
{
    const double *p = km_pt(c->m, pid);
    uint32_t t0;
    gtet_status s = km_find_conflict(c, p, &t0, local_first);
    if (s != GTET_OK) return s;
    if (t0 == UINT32_MAX) {
        c->conflicts++;
        *deferred = 1;
        return GTET_OK;
    }
    size_t ncav = 0, nb = 0;
    int foreign = 0;
    const int outside = km_is_ghost(c->m, t0);  /* p beyond a hull facet (the walk's ghost) */
    /* the search's instance for a parallel pass, or for a serial insertion (no ownership) */
    s = c->colour ? dig(c, pid, p, t0, &ncav, &nb, &foreign, deferred, local_first, 1)
                  : dig(c, pid, p, t0, &ncav, &nb, &foreign, deferred, local_first, 0);
    if (s != GTET_OK) return s;
    if (*deferred) {
        c->defer_hint = t0;  /* in conflict with p: next to it (rolled back, live) */
        return s;
    }
    s = fill(c, ncav, nb, foreign, deferred);
    if (*deferred) c->defer_hint = t0;
    if (__builtin_expect(outside, 0) && s == GTET_OK && !*deferred) remember_ghost(c, nb);
    return s;
}

/* the two instances compiled with AVX2 (insert_avx2.c), when the build has them */
gtet_status km_insert_static_first_avx2(kctx *c, uint32_t pid, int *deferred);
gtet_status km_insert_local_first_avx2(kctx *c, uint32_t pid, int *deferred);
#endif
