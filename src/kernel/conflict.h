/* conflict.h -- the conflict test shared by the point location (locate.c) and the cavity
 * search (insert.c); the location step km_insert starts with is in walk.h.
 *
 * km_conflicts is static inline on purpose: the cavity search calls it ~50 times a point and
 * must keep it inlined with the insphere filter (NOTES.md E16: +6.5% when it was not). */
#ifndef GTET_KERNEL_CONFLICT_H
#define GTET_KERNEL_CONFLICT_H
#include "kmesh.h"

/* Does point p conflict with tet t (perturbed insphere, or the hull rule for a ghost)?  tv, V
 * and seps are c->m's tet vertices, coordinates and static insphere bound, local_first is
 * c->local_first (km_filter_order): the cavity search reads them once a point and passes
 * them, where each call would load them again (stores through the boundary records may
 * alias them for the compiler; NOTES.md E142).
 * always_inline: gcc's size heuristics stop inlining it once the filter keeps its record of
 * an undecided call (filter.h pred_insphere_keep_): paraboloid 100k +4.5% instructions. */
__attribute__((always_inline)) static inline int km_conflicts_in(kctx *c, const uint32_t *tv,
                                                                 const double *V, double seps,
                                                                 int local_first, uint32_t t,
                                                                 const double *p)
{
    const kmesh *m = c->m;
    const uint32_t *v = tv + 4 * (size_t)t;
    if (v[3] == KM_GHOST)
        return pred_ghost_conflict_st_log(V + 3 * (size_t)v[0], V + 3 * (size_t)v[1],
                                          V + 3 * (size_t)v[2], p, &m->ps, &c->cnt,
                                          c->sos_log) > 0;
    const double *a = V + 3 * (size_t)v[0], *b = V + 3 * (size_t)v[1];
    const double *cc = V + 3 * (size_t)v[2], *d = V + 3 * (size_t)v[3];
    /* the filter inline (most calls stop here); the full chain counts its own call.  Its
     * order, static test first or the thread's level first (or, without AVX2, the semi-static
     * bound first), changes which branches run, never the answer (filter_packed.h
     * pred_insphere_filter_packed_lv, pred_insphere_filter_packed_sf). */
    double minors[PRED_IS_NMINORS];
#ifdef PRED_INSPHERE_PACKED
    int s = local_first
                ? pred_insphere_filter_packed_lv_or_(a, b, cc, d, p, seps, &c->level, minors,
                                                     &c->static_misses)
                : pred_insphere_filter_packed(a, b, cc, d, p, seps, minors, &c->static_misses);
#else
    (void)local_first;  /* one order only: the sampler counts no miss and never switches */
    int s = pred_insphere_filter(a, b, cc, d, p, seps, minors);
#endif
    if (s != 0) {
        c->cnt.insphere_calls++;
        return s > 0;
    }
    return pred_insphere_sos_rest_log(a, b, cc, d, p, &m->ps, minors, &c->cnt, c->sos_log) > 0;
}

#if defined(PRED_INSPHERE_PACKED) && defined(__AVX2__)
/* km_conflict_bit's calls the first bound leaves: what pred_insphere_filter_packed and
 * pred_insphere_filter_packed_lv do after their first bound (the miss counted, the level
 * moved), then the rest as km_conflicts_in; a function of its own, so that the search's loop
 * keeps its registers */
static __attribute__((noinline)) unsigned km_conflict_rest(kctx *c, const pred_is_lanes4_ *L,
                                                           double det, double seps,
                                                           int local_first, const double *a,
                                                           const double *b, const double *cc,
                                                           const double *d, const double *p)
{
    ++c->static_misses;
    if (local_first) pred_insphere_level_move_(&c->level, pred_insphere_lane_max_(L), seps);
    double minors[PRED_IS_NMINORS];
    const int s = pred_insphere_packed4_rest_(L, det, seps, minors);
    if (s != 0) {
        c->cnt.insphere_calls++;
        return s > 0;
    }
    return pred_insphere_sos_rest_log(a, b, cc, d, p, &c->m->ps, minors, &c->cnt, c->sos_log) > 0;
}
#endif

/* km_conflicts_in for the cavity search (insert_steps.h dig), as 0 or 1 for the caller to
 * use as data: on the common path the only branch is the filter's "decided", taken almost
 * always, and the answer is the sign of det~ (NOTES.md E252).  The same answers, counts and
 * filter-order state as km_conflicts_in: det~ and the first bound are the filter's
 * (pred_insphere_filter_packed's seps, or pred_insphere_filter_packed_lv's level bound when
 * every translated coordinate is inside the level, else seps), |det~| > bound is its two
 * comparisons in one (a NaN or an infinite bound decides nothing either way), and a call it
 * leaves runs the filter's rest on the same values (km_conflict_rest).  Without AVX2, and for
 * a ghost, km_conflicts_in itself. */
__attribute__((always_inline)) static inline unsigned km_conflict_bit(kctx *c, const uint32_t *tv,
                                                                      const double *V, double seps,
                                                                      int local_first, uint32_t t,
                                                                      const double *p)
{
#if defined(PRED_INSPHERE_PACKED) && defined(__AVX2__)
    const uint32_t *v = tv + 4 * (size_t)t;
    if (__builtin_expect(v[3] != KM_GHOST, 1)) {
        const double *a = V + 3 * (size_t)v[0], *b = V + 3 * (size_t)v[1];
        const double *cc = V + 3 * (size_t)v[2], *d = V + 3 * (size_t)v[3];
        pred_is_lanes4_ L;
        const double det = pred_insphere_lanes4_(a, b, cc, d, p, &L);
        __m256d m;
        const double thr = local_first ? pred_insphere_level_bound_(&L, &c->level, seps, &m) : seps;
        if (__builtin_expect(__builtin_fabs(det) > thr, 1)) {
            c->cnt.insphere_calls++;
            return det > 0;
        }
        return km_conflict_rest(c, &L, det, seps, local_first, a, b, cc, d, p);
    }
#endif
    return (unsigned)km_conflicts_in(c, tv, V, seps, local_first, t, p);
}

/* km_conflicts_in on c->m's arrays and bound */
__attribute__((always_inline)) static inline int km_conflicts(kctx *c, uint32_t t, const double *p)
{
    const kmesh *m = c->m;
    return km_conflicts_in(c, m->tv, m->v, m->ps.is_seps, c->local_first, t, p);
}

/* The insphere filter's order for the next insertions.  The static test decides almost every
 * call on uniform points and is then one well-predicted branch.  Where the mesh is finer than
 * the box's static bound sees (surface samples, a dense cluster, uniform points past ~10M: the
 * static test leaves a third to all of the calls), the level filter runs first (NOTES.md
 * E188): a static bound for the thread's current level, a power of two above the tuples'
 * translated coordinates, checked by four lane comparisons, which decides like the static test
 * at the mesh's own scale; it replaced the semi-static-first order there (E169, E172).  Every
 * KM_ORDER_PERIOD insertions of a thread, KM_ORDER_SAMPLE of them run static-first and count
 * the calls the static test leaves; when that share exceeds KM_ORDER_SHARE_LO, KM_ORDER_SAMPLE
 * more run level-first and count the calls the level and the static test both leave, and the
 * rest of the period runs level-first unless that share exceeds KM_ORDER_SHARE_HI: points on
 * a sphere, whose tuples are nearly co-spherical at every scale, leave both tests nearly every
 * call, and there the static test first is one predictable branch (E172).  (The AVX2 build's;
 * the SSE2 one runs the semi-static bound first where the AVX2 one runs the level, and counts
 * the calls it leaves.)  Insertions follow the Moore curve, so the choice follows the
 * density along it.  The answers are the same either way: the mesh never depends on it. */
#define KM_ORDER_SAMPLE 256u
#define KM_ORDER_PERIOD 4096u
#define KM_ORDER_SHARE_LO_NUM 1u   /* KM_ORDER_SHARE_LO = 1/3 */
#define KM_ORDER_SHARE_LO_DEN 3u
#define KM_ORDER_SHARE_HI_NUM 9u   /* KM_ORDER_SHARE_HI = 9/10 */
#define KM_ORDER_SHARE_HI_DEN 10u
void km_filter_order(kctx *c);

/* locate.c: a ghost in conflict with p found by a walk over the hull from c->last_ghost, or
 * UINT32_MAX (in a parallel pass also when the walk meets a ghost not this thread's); a linear
 * scan for a conflicting tet (the visibility walk's fallback; the walk itself and the location
 * step, km_find_conflict, are in walk.h). */
uint32_t km_hull_search(kctx *c, const double *p);
gtet_status km_scan_for_conflict(kctx *c, const double *p, uint32_t *found);
#endif
