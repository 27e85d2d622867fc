/* starts.c -- where a thread of a parallel pass starts and restarts walking (parallel.c calls
 * these before the pass's barrier).  Every function here only reads the mesh: it runs while no
 * thread writes it (proofs/parallel.md O4), and what it returns is a tet of the calling
 * thread's colour, which no other thread may kill during the pass. */
#include "starts.h"

/* c->last = the first live tet (this thread's, if `owned`) scanning the slots cyclically from
 * `from`; 0 if there is none. */
static int scan_start(kctx *c, size_t from, int owned)
{
    const kmesh *m = c->m;
    const size_t nt = m->nt;
    for (size_t k = 0; k < nt; k++) {
        const size_t t = (from + k) % nt;
        if (!km_dead(m, t) && (!owned || km_owned(c, (uint32_t)t))) {
            c->last = (uint32_t)t;
            return 1;
        }
    }
    return 0;
}

/* A live tet of this thread's colour to start walking from.  First the tet in conflict with
 * one of the slice's first START_TRIES points that is this thread's (km_locate, each walk
 * from the last tet found): a slice rarely starts where the thread's last one ended, and a
 * walk from there that leaves the colour defers its point and, starting again from the same
 * tet, every next one until the thread gives up on its slice (NOTES.md E5).  Else its last
 * tet if still good, else the first one found scanning from a slot proportional to its colour
 * (tets are roughly in Moore order of creation).  Read-only; runs before the pass's barrier,
 * while no thread writes the mesh (O4). */
#define START_TRIES 64
int kpar_find_start(kctx *c, int nthreads, const uint32_t *pts, size_t np)
{
    const kmesh *m = c->m;
    const size_t from = m->nt / (size_t)nthreads * c->mine;
    const int live = (c->last < m->nt && !km_dead(m, c->last)) || scan_start(c, from, 0);
    if (live) {
        const uint32_t last = c->last;
        for (size_t i = 0; i < np && i < START_TRIES; i++) {
            const uint32_t t = km_locate(c, km_pt(m, pts[i]));
            if (t == UINT32_MAX) break;
            c->last = t;
            if (km_owned(c, t)) return 1;
        }
        c->last = last;
        if (km_owned(c, c->last)) return 1;
    }
    return scan_start(c, from, 1);
}

/* Restart tets along the slice (NOTES.md E13): ck[j] (0 < j < nck) is a tet of this thread
 * in conflict with one of the points at slice offset np j / nck .. + 3, found like
 * find_start's by walks that may cross any colour, or UINT32_MAX.  nck = checkpoints(np): 64,
 * and one a CK_SPACING points in long slices, up to KPAR_CK_MAX (E100: a deferred walk's thread
 * walks on sooner; the sphere's 833k-point round defers 89.7k points with 64, 45.5k with 256).
 * Read-only, before the pass's barrier (O4).  During the pass only this thread writes such a
 * slot: it is its tet, which no other thread may kill, and once killed the slot is on its free
 * list. */
#define CK_MIN 64
#define CK_SPACING 1024
int kpar_checkpoints(size_t np)
{
    const size_t k = np / CK_SPACING;
    return k < CK_MIN ? CK_MIN : k > KPAR_CK_MAX ? KPAR_CK_MAX : (int)k;
}

void kpar_find_checkpoints(kctx *c, const uint32_t *pts, size_t np, int nck, uint32_t ck[])
{
    const kmesh *m = c->m;
    const uint32_t last = c->last;
    for (int j = 0; j < nck; j++) ck[j] = UINT32_MAX;
    for (int j = 1; np >= 4 * (size_t)nck && j < nck; j++)
        for (size_t i = np * (size_t)j / (size_t)nck, k = 0; k < 4; k++) {
            const uint32_t t = km_locate(c, km_pt(m, pts[i + k]));
            if (t == UINT32_MAX) break;
            c->last = t;
            if (km_owned(c, t)) {
                ck[j] = t;
                break;
            }
        }
    c->last = last;
}


/* run_tet[j]: a tet of this thread in conflict with one of the points at slice offset
 * run_at[j] .. + 3, found like the checkpoints' by walks from the previous run's (the runs
 * follow each other along the curve); UINT32_MAX when none is.  Read-only, before the barrier
 * (O4). */
void kpar_find_runs(kctx *c, const uint32_t *pts, size_t np, kpar_restarts *R)
{
    const kmesh *m = c->m;
    const uint32_t last = c->last;
    for (size_t j = 0; j < R->nruns; j++) {
        R->run_tet[j] = UINT32_MAX;
        for (size_t i = R->run_at[j]; i < np && i < (size_t)R->run_at[j] + 4; i++) {
            const uint32_t t = km_locate(c, km_pt(m, pts[i]));
            if (t == UINT32_MAX) break;
            c->last = t;
            if (km_owned(c, t)) {
                R->run_tet[j] = t;
                break;
            }
        }
    }
    c->last = last;
}

/* The hints deferred points left in the pass before (kctx.defer_hint): a tet near the point
 * that the walk reached or the cavity started from.  Since then the tet may have died, its
 * slot may hold another tet, and the colours have changed: kept only where it is live and this
 * thread's now.  Read-only on the mesh, before the barrier (O4). */
void kpar_check_hints(kctx *c, const uint32_t *pts, size_t np, uint32_t *hint)
{
    const kmesh *m = c->m;
    for (size_t i = 0; i < np; i++) {
        const uint32_t t = hint[pts[i]];
        if (t != UINT32_MAX && (t >= m->nt || km_dead(m, t) || !km_owned(c, t)))
            hint[pts[i]] = UINT32_MAX;
    }
}
