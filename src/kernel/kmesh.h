/* mesh.h -- the kernel's working mesh and per-thread insertion context (prefix km_).
 *
 * Struct of arrays, as in the seed paper and HXT:
 *   tv[4t+i]  vertex i of tet t (uint32); KM_GHOST is the vertex at infinity, always in slot 3;
 *   tn[4t+i]  4*u+j: the tet u across the facet opposite vertex i, and the index j of that
 *             facet in u, so the back link is tn[4u+j] == 4t+i;
 *   the top bit of tv[4t] (KM_DEAD) marks a deleted tet (slot 0 is never the ghost, and
 *             vertex ids stay below 2^31), so a neighbour's liveness is read from the
 *             same cache line as its vertices.
 * Finite tets are positively oriented (orient3d > 0).  A ghost tet (a,b,c,G) has its finite
 * facet ordered so that orient3d(a,b,c,x) < 0 for the points x of the hull: the vertex at
 * infinity is on the positive side, and every ghost is "positively oriented" too, which is
 * what lets a cavity replace any vertex by the new point without re-orienting (star-shaped
 * cavity, lifted picture).  The 4*u+j packing limits a mesh to 2^30 - 1 tet slots.
 * Nothing here is global: a kmesh is shared by the threads of one call, a kctx belongs to one
 * thread (cavity buffers, counters, adjacency table).
 */
#ifndef GTET_KMESH_H
#define GTET_KMESH_H

#include <stddef.h>
#include <stdint.h>

#include "gigatet.h"
#include "../pred/pred.h"

#define KM_GHOST UINT32_MAX
#define KM_DEAD 0x80000000u
#define KM_MAX_VERTICES (KM_DEAD - 1)
#define KM_MAX_SLOTS ((UINT32_C(1) << 30) - 1) /* so 4u+j < UINT32_MAX: that value is never a handle */
#define KM_LOC_MAX 64   /* cavity-local vertex ids for the fast adjacency table */
#define KM_SLOT_BLOCK 4096 /* fresh slots a thread claims at once in a parallel pass */

typedef struct kmesh {
    const double *v;    /* 3 doubles per vertex */
    size_t nv;
    uint32_t *tv;
    uint32_t *tn;
    size_t nt;          /* slots in use (live and deleted) */
    size_t cap;         /* slots allocated */
    int wide;           /* nonzero: tv and tn each allocated with room for 32 bytes a slot and
                           16 more (twice what the slots take; the pages past the slots in use
                           are never touched), and km_finalize hands them over unshrunk: the
                           distributed mode widens the result to 64-bit entries where it lies
                           (gtet_triangulate_wide, src/mpi/mpi_output.c, NOTES.md E130) */
    uint8_t *vloc;      /* cavity-local id of each vertex (scratch, nv bytes) */
    pred_static ps;     /* static bounds / lattice exactness for these vertices (pred.h) */
    double box[6];      /* their bounding box (min x, y, z, max x, y, z) */
    /* NULL, or asked before the arrays grow past their first capacity (the memory guard's
     * second check: a mesh with more tets per point than the estimate, src/api/memory.c
     * mem_grow_guard): the slots in use span used_bytes of the cap_bytes allocated, the
     * arrays need at least min_bytes and would grow to *want_bytes; the guard may lower
     * *want_bytes (never below min_bytes) to what the machine can still give, or return
     * GTET_ERR_OUT_OF_MEMORY (it says why). */
    gtet_status (*grow_guard)(void *user, size_t used_bytes, size_t cap_bytes, size_t min_bytes,
                              size_t *want_bytes);
    void *grow_user;
} kmesh;

/* One boundary facet of a cavity: the new tet it becomes (the deleted tet's vertices with the
 * new point in slot f) and the outer facet it is glued to. */
typedef struct kbound {
    uint32_t v[4];
    uint32_t outer;     /* 4*u+j of the facet outside the cavity */
    uint32_t f;         /* slot of the new point */
} kbound;

typedef struct kctx {
    /* each thread's context starts on its own cache line (and sizeof is a multiple of 64), so
     * that one thread's counters never share a line with another's (false sharing slows a
     * parallel pass measurably: NOTES.md E1) */
    _Alignas(64) kmesh *m;
    pred_counters cnt;
    pred_sos_log *sos_log;  /* this thread's record of the perturbation's decisions, or NULL
                               (gtet_options.degeneracies off) */
    uint32_t *cav;      /* deleted tets of the current cavity */
    size_t cav_cap;
    kbound *bnd;        /* boundary facets of the current cavity */
    size_t bnd_cap;
    uint32_t *freelist; /* deleted slots not reused yet */
    size_t nfree, free_cap;
    uint32_t last;      /* a live tet near the last insertion: the next walk starts here */
    uint32_t last_ghost; /* a ghost the last insertion made when its point was outside the
                            hull (UINT32_MAX: none): the next search over the hull starts
                            here (serial only, NOTES.md E32) */
    uint64_t rng;
    uint64_t walk_steps, walk_fallbacks, tets_created, big_cavities;
    uint64_t table[KM_LOC_MAX * KM_LOC_MAX]; /* directed edge -> cavity number << 32 | facet
                                              * handle (adjacency_fast) */
    uint32_t cavity_gen;   /* cavities linked by adjacency_fast (the stamp; wraps after 2^32) */
    uint64_t *htab;     /* fallback edge table for cavities with > 63 boundary vertices */
    size_t htab_cap;
    /* parallel passes (parallel.c): vertex colours, this thread's colour, a block of fresh
     * slots claimed from the shared counter.  colour == NULL: serial, no ownership checks,
     * the arrays may grow. */
    const uint8_t *colour;
    uint8_t mine;
    uint8_t own_min;    /* vertices of its colour that make a tet this thread's: 4 or 3 */
    int out_of_room;    /* a parallel insertion was deferred for lack of slots */
    size_t blk_next, blk_end;
    uint64_t conflicts; /* insertions rolled back on a colour conflict */
    uint32_t defer_hint; /* a deferred insertion's first cavity tet (in conflict with its
                            point), or UINT32_MAX (the walk met another thread's tet first: its
                            stop can be far from the point): the point's next pass may start
                            its walk there (parallel.c, NOTES.md E177) */
    /* the insphere filter's order (conflict.h km_filter_order): local_first set, a bound at
     * the tuple's own scale first (the level filter; without AVX2 the semi-static bound),
     * else the static test, fixed by the box, first; a sample
     * of static-first insertions (sampling 1) counts the calls the static test leaves, then
     * one of level-first insertions (sampling 2) those both tests leave */
    uint8_t local_first, sampling;
    uint8_t avx2;                 /* km_insert runs the AVX2 instances (insert_avx2.c) */
    uint8_t walk_inside;          /* the last walk ended in a finite tet whose tested facets
                                     all put the point strictly inside (walk.h) */
    uint32_t order_left;          /* insertions before the order is reconsidered */
    uint64_t static_misses, sample_calls0;
    pred_is_level level;          /* the level filter's (pred_insphere_filter_packed_lv) */
} kctx;

static inline int km_is_ghost(const kmesh *m, uint32_t t) { return m->tv[4 * (size_t)t + 3] == KM_GHOST; }
static inline int km_dead(const kmesh *m, size_t t) { return (m->tv[4 * t] & KM_DEAD) != 0; }
static inline void km_kill(kmesh *m, size_t t) { m->tv[4 * t] |= KM_DEAD; }
static inline void km_revive(kmesh *m, size_t t) { m->tv[4 * t] &= ~KM_DEAD; }
static inline const double *km_pt(const kmesh *m, uint32_t v) { return m->v + 3 * (size_t)v; }

gtet_status km_init(kmesh *m, const double *v, size_t nv, size_t slots_hint, int threads,
                    int wide);
void km_free(kmesh *m);
gtet_status km_reserve(kmesh *m, size_t slots);

void kctx_init(kctx *c, kmesh *m, uint64_t seed);
void kctx_free(kctx *c);

/* Build the first tet on vertices a,b,c,d (not coplanar) and its four ghosts. */
gtet_status km_first_tet(kctx *c, uint32_t a, uint32_t b, uint32_t cc, uint32_t d);

/* Insert vertex p (not yet in the mesh, distinct from every vertex in it).  In a parallel
 * pass (c->colour set) the insertion is abandoned, with nothing written, when the walk or the
 * cavity meets a tet that is not this thread's (km_owned), the walk runs out of steps, or no
 * slot is left: *deferred = 1. */
gtet_status km_insert(kctx *c, uint32_t p, int *deferred);

/* The tet in conflict with p that a visibility walk from c->last (a live tet) finds,
 * crossing any tet (c->colour is ignored), or UINT32_MAX when the walk's step budget runs out
 * (no scan).  Reads the mesh and writes only c's own counters and generator: a parallel pass
 * calls it before its barrier, while no thread writes the mesh (find_start in parallel.c). */
uint32_t km_locate(kctx *c, const double *p);

/* End of a parallel pass: the unused fresh slots of this thread go to its free list. */
gtet_status km_flush_block(kctx *c);

/* In a parallel pass, tet t is this thread's when all its finite vertices have the thread's
 * colour (own_min 4: the and the paper's rule), or, once a run has switched
 * (own_min 3, see kpar_round), when at least three of its four vertices have it (the vertex
 * at infinity has none: a ghost needs its three finite vertices).  Either way no tet is two
 * threads', and a tet next to one of this thread's tets is no other thread's
 * (proofs/parallel.md C1).  Returns 0: not owned; 1: owned, no vertex of another colour;
 * 2: owned with one finite vertex of another colour (a "foreign" vertex, own_min 3 only: its
 * vloc is not this thread's to use, adjacency_fast_foreign keeps it in a local list). */
static inline int km_owned(const kctx *c, uint32_t t)
{
    const uint32_t *v = c->m->tv + 4 * (size_t)t;
    const uint8_t *col = c->colour;
    const uint8_t k = c->mine;
    const int ghost = v[3] == KM_GHOST;
    if (col[v[0]] == k && col[v[1]] == k && col[v[2]] == k && (ghost || col[v[3]] == k))
        return 1;  /* the common case inside a region */
    if (c->own_min == 4) return 0;
    const int n = (col[v[0]] == k) + (col[v[1]] == k) + (col[v[2]] == k) +
                  (!ghost && col[v[3]] == k);
    return n >= 3 ? 2 : 0;
}

/* km_owned's answer without a branch on the colours (for the cavity search, which asks it of
 * every tet it tests): a ghost's missing fourth colour is read as its vertex 0's again, so
 * that four matches mean its three finite vertices match */
static inline int km_owned_bits(const kctx *c, uint32_t t)
{
    const uint32_t *v = c->m->tv + 4 * (size_t)t;
    const uint8_t *col = c->colour;
    const uint8_t k = c->mine;
    const unsigned ghost = v[3] == KM_GHOST;
    const uint32_t v3 = ghost ? v[0] : v[3];
    const unsigned n = (unsigned)(col[v[0]] == k) + (unsigned)(col[v[1]] == k) +
                       (unsigned)(col[v[2]] == k) + (unsigned)(col[v3] == k);
    const unsigned all = n == 4;
    const unsigned three = (n == 3) & !ghost & (c->own_min == 3);
    return (int)(all | three << 1);
}
#endif
