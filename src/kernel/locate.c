/* locate.c -- point location for the insertion (insert.c): a tet in conflict with the new
 * point, from which the cavity search starts.
 *
 * Why it is correct: any tet in conflict with p starts the same cavity (the perturbed
 * Delaunay tetrahedrization is unique, proofs/perturbation.md), and every tet returned here
 * was tested with the exact conflict test (km_conflicts) or is the end of the visibility walk:
 *  - walk: from a live tet, cross a facet only when the point is strictly beyond it (exact
 *    orient3d < 0 with the point in that facet's slot).  A finite tet with no such facet
 *    contains the point in its closure, and a point of a closed tet other than its vertices is
 *    strictly inside its circumsphere, so that tet conflicts; a ghost is entered only through
 *    its finite facet with the point strictly beyond, so it conflicts too.  The facet order is
 *    randomised; after a step budget the walk gives up and a linear scan finds a conflicting
 *    tet, so the walk always terminates (proofs/termination.md).  km_find_conflict checks the
 *    walk's tet once more and scans when it does not conflict.  The walk and km_find_conflict
 *    are in walk.h (each instance of km_insert has its own copy); here are km_locate, the
 *    hull walk and the scan.
 *  - the hull walk (serial, after an insertion from outside the hull) only proposes a ghost;
 *    km_find_conflict takes it only when km_conflicts says so, else it walks.
 */
#include "walk.h"

/* Linear scan for a live tet in conflict with p: the walk's guaranteed fallback. */
gtet_status km_scan_for_conflict(kctx *c, const double *p, uint32_t *found)
{
    const kmesh *m = c->m;
    c->walk_fallbacks++;
    for (size_t t = 0; t < m->nt; t++) {
        if (km_dead(m, t)) continue;
        if (km_conflicts(c, (uint32_t)t, p)) {
            *found = (uint32_t)t;
            return GTET_OK;
        }
    }
    return GTET_ERR_INTERNAL;  /* a point outside every circumsphere and beyond no hull facet */
}

uint32_t km_locate(kctx *c, const double *p)
{
    const uint8_t *colour = c->colour;
    c->colour = NULL;  /* every tet may be crossed: nothing is written */
    uint32_t t = UINT32_MAX;
    if (km_walk_t(c, p, &t, 0) != GTET_OK) t = UINT32_MAX;
    c->colour = colour;
    return t;
}

/* A point outside the hull conflicts with the ghosts of the hull facets it sees (the hull
 * rule), and consecutive points of a surface sample (sphere, paraboloid: every point on the
 * hull) are close, so after an insertion from outside the hull the next point is first
 * located over the hull, from one of the previous point's new ghosts (NOTES.md E32), by a
 * walk over the ghosts in the central projection from o, the centre of the points' bounding
 * box: the ray from a point o inside the hull to a point p outside it leaves the hull through
 * a facet that p is strictly beyond, and that facet's ghost conflicts.  A ghost (a,b,c,G) has
 * orient3d(a,b,c,x) < 0 for the points x of the hull (kmesh.h), so for o inside the hull its
 * vertex v_i is on the negative side of neither plane (v_i+1, v_i+2, o) and the walk crosses
 * the hull edge opposite v_i (the ghost's facet i) when orient3d(v_i+1, v_i+2, o, p) < 0; where
 * no edge is to be crossed, the ghost is tested.  The directions are plain double arithmetic
 * and o may be outside the hull while it is small or when the surface is not closed: the walk
 * only proposes a ghost, which is tested exactly (a miss falls back to the visibility walk,
 * which crosses the slivers under a convex surface; NOTES.md E60).
 * In a parallel pass (proofs/parallel.md R1, O13) c->last_ghost was made by this thread's
 * previous insertion in the same pass (insert_slice clears it at the pass's start), so it is
 * live and this thread's; each step reads tv of the next ghost, which is adjacent to the
 * current, owned one, and goes on only if that ghost is this thread's too; else the search
 * gives up and the visibility walk (which defers) takes over. */
#define KM_HULL_STEPS 32

/* The sign of orient3d(a, b, o, p) (det[b-a; o-a; p-a], pred.h's convention) in plain
 * double arithmetic: a direction for the hull walk, never trusted. */
static inline double orient_approx(const double *a, const double *b, const double *o,
                                   const double *p)
{
    const double px = b[0] - a[0], py = b[1] - a[1], pz = b[2] - a[2];
    const double qx = o[0] - a[0], qy = o[1] - a[1], qz = o[2] - a[2];
    const double rx = p[0] - a[0], ry = p[1] - a[1], rz = p[2] - a[2];
    return (px * (qy * rz - qz * ry) + py * (qz * rx - qx * rz)) + pz * (qx * ry - qy * rx);
}

uint32_t km_hull_search(kctx *c, const double *p)
{
    const kmesh *m = c->m;
    uint32_t g = c->last_ghost;
    size_t nt_now;  /* bumped by other threads' atomic captures in a parallel pass */
#pragma omp atomic read
    nt_now = m->nt;
    if (g >= nt_now || km_dead(m, g) || !km_is_ghost(m, g)) return UINT32_MAX;
    const double o[3] = {0.5 * (m->box[0] + m->box[3]), 0.5 * (m->box[1] + m->box[4]),
                         0.5 * (m->box[2] + m->box[5])};
    uint32_t entry = UINT32_MAX;  /* handle 4g+i of the edge we came in through */
    for (unsigned step = 0; step < KM_HULL_STEPS; step++) {
        const uint32_t *v = m->tv + 4 * (size_t)g;
        const unsigned r = step % 3;  /* a varying first edge: no fixed order can cycle */
        int moved = 0;
        for (unsigned k = 0; k < 3; k++) {
            const unsigned i = (r + k) % 3;
            const uint32_t h = 4 * g + i;
            if (h == entry) continue;
            if (orient_approx(km_pt(m, v[(i + 1) % 3]), km_pt(m, v[(i + 2) % 3]), o, p) < 0) {
                entry = m->tn[h];
                g = entry >> 2;
                if (c->colour && !km_owned(c, g)) return UINT32_MAX;  /* R1: tv only */
                moved = 1;
                break;
            }
        }
        if (!moved) return km_conflicts(c, g, p) ? g : UINT32_MAX;
    }
    return UINT32_MAX;
}
