/* check_internal.h -- shared state of the exact checker (src/check/, prefix chk_).
 *
 * The checker runs in stages (check.c: inputs and vertices; check_topo.c: facets, adjacency,
 * hull surface, Euler characteristic and vertex links; check_geom.c: orientation, local
 * Delaunay, the hull rule, convexity of the hull, volume, the optional full test).  Each stage
 * returns GTET_OK or stops at the first violation, which chk_fail() writes into the report.
 * All geometry goes through the GMP oracle (src/oracle/); nothing here uses src/pred/.
 */
#ifndef GTET_CHECK_INTERNAL_H
#define GTET_CHECK_INTERNAL_H

#include "gigatet.h"

#define CHK_KNOWN_FLAGS                                                                     \
    ((unsigned)GTET_CHECK_FULL | (unsigned)GTET_CHECK_NO_FILTER | (unsigned)GTET_CHECK_DELAUNAY | \
     (unsigned)GTET_CHECK_ANY_ORIENTATION)

typedef struct chk_ctx {
    /* the mesh under test */
    const double *vertices;     /* 3*nv */
    size_t nv;
    const uint32_t *tets;       /* 4*nt */
    size_t nt;
    const uint32_t *neighbors;  /* 4*nt or NULL */
    /* the input (optional) */
    const double *xyz;          /* 3*n or NULL */
    size_t n;
    const uint32_t *input_map;  /* n or NULL: checked against xyz when given (gtet_check) */
    unsigned flags;
    int closed;                 /* GTET_CHECK_DELAUNAY: ties allowed (closed Delaunay property) */
    gtet_check_report *report;  /* never NULL inside the checker */
    const char *stage;          /* the running stage's identifier (gtet_check_violation.stage) */
    int want_cells;             /* fill cell[] (gtet_diff) */
    int threads;                /* every parallel region's team: what OpenMP gives a region
                                   here and the process can start (chk_run) */
    int (*cancel)(void *user);  /* gtet_check_options.cancel, or NULL */
    void *cancel_user;
    int level;                  /* omp_get_level() of the calling thread (chk_run) */
    int cancelled;              /* set once cancel returned nonzero; read atomically by every
                                   thread (chk_stop), written by the calling thread only */
    /* built by the stages */
    uint32_t *adj;              /* 4*nt: rebuilt adjacency, GTET_NO_TET on the hull */
    uint32_t *hull;             /* 3*nh: hull facets, outward oriented (ghost orientation) */
    uint32_t *hull_tf;          /* nh: 4*t+f of the tet facet behind each hull facet */
    uint32_t *hull_adj;         /* 3*nh: hull facet across edge (hull[3h+i], hull[3h+(i+1)%3]) */
    size_t nh;
    size_t interior_facets;
    uint32_t *own_tets;         /* GTET_CHECK_ANY_ORIENTATION: the tets with every negative one
                                   turned positive (vertices 0 and 1 swapped); tets points here */
    uint32_t *own_neighbors;    /* the neighbors permuted alike (when given) */
    uint8_t *unused;            /* nv flags (or NULL when every vertex is in a tet): 1 for a vertex
                                   in no tet whose point is that of a vertex in one */
    uint32_t *cell;             /* want_cells: nt union-find parents joining the tets across
                                   interior facets whose five vertices are co-spherical, so that
                                   each class is the triangulation of one Delaunay cell */
    uint8_t *cell_hull;         /* want_cells: nt flags, 1 for a tet with a facet on the hull */
} chk_ctx;

/* Record the first violation (printf-style message) and return GTET_ERR_CHECK_FAILED. */
gtet_status chk_fail(chk_ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
gtet_status chk_oom(chk_ctx *c);
/* Record what the next chk_fail is about: tets t0, t1 (GTET_CHECK_NONE when absent) and nv
 * vertex ids with their coordinates. */
void chk_note(chk_ctx *c, uint64_t t0, uint64_t t1, int nv, const uint32_t *v);
/* The number of used mesh vertices w with orient3d(a,b,c,w) == 0 (coplanar) when d is NULL,
 * else with insphere(a,b,c,d,w) == 0 (co-spherical): the size of a tie's group. */
uint64_t chk_group_size(const chk_ctx *c, const uint32_t *abc, const uint32_t *abcd);
uint32_t chk_find(uint32_t *parent, uint32_t x);

/* Facet f of tet t (opposite its vertex f) as seen from outside the tet: (o[0], o[1], o[2])
 * with orient3d(o[0], o[1], o[2], tets[4t+f]) < 0 when the tet is positively oriented. */
void chk_outward_facet(const uint32_t *tet, int f, uint32_t o[3]);

/* The predicates the stages use (check_filter.c): the oracle's exact sign, decided first by
 * interval arithmetic when c->flags lacks GTET_CHECK_NO_FILTER. */
int chk_orient3d(const chk_ctx *c, const double *a, const double *b, const double *cc,
                 const double *d);
int chk_insphere(const chk_ctx *c, const double *a, const double *b, const double *cc,
                 const double *d, const double *e);
int chk_insphere_sos(const chk_ctx *c, const double *a, const double *b, const double *cc,
                     const double *d, const double *e);
int chk_ghost_conflict(const chk_ctx *c, const double *a, const double *b, const double *cc,
                       const double *e);

/* Cancellation (gtet_check_options.cancel).  chk_poll calls the callback when it runs on the
 * calling thread -- in serial code, or as thread 0 of a region the checker started, which
 * OpenMP makes the encountering thread -- and returns the shared flag; a callback that once
 * returned nonzero is not called again.  chk_stop(c, i) is for item i of a loop: it polls at
 * every 1024th item and otherwise only reads the flag (nothing at all without a callback), so
 * every thread leaves its share of the loop within an item of the calling thread's poll.
 * chk_cancelled writes the report of a cancelled check and returns GTET_ERR_CANCELLED. */
#define CHK_POLL_MASK 1023u
int chk_poll(chk_ctx *c);
gtet_status chk_cancelled(chk_ctx *c);
static inline int chk_is_cancelled(const chk_ctx *c)
{
    return c->cancel && __atomic_load_n(&c->cancelled, __ATOMIC_RELAXED);
}
static inline int chk_stop(chk_ctx *c, size_t i)
{
    if (!c->cancel) return 0;
    if ((i & CHK_POLL_MASK) == 0) return chk_poll(c);
    return __atomic_load_n(&c->cancelled, __ATOMIC_RELAXED);
}
/* The same for item i of a serial loop whose items are cheap (a few memory accesses, a binary
 * search): polled every 16384 items, a few milliseconds. */
#define CHK_POLL_SERIAL_MASK 16383u
static inline int chk_stop_serial(chk_ctx *c, size_t i)
{
    return c->cancel && (i & CHK_POLL_SERIAL_MASK) == 0 && chk_poll(c);
}

gtet_status chk_inputs(chk_ctx *c);        /* check.c */
gtet_status chk_orientation(chk_ctx *c);   /* check_geom.c */
gtet_status chk_facets(chk_ctx *c);        /* check_topo.c: fills adj, hull, hull_tf */
gtet_status chk_hull_surface(chk_ctx *c);  /* check_topo.c: fills hull_adj */
gtet_status chk_euler_links(chk_ctx *c);   /* check_topo.c */
gtet_status chk_delaunay(chk_ctx *c);      /* check_geom.c */
gtet_status chk_hull_convex(chk_ctx *c);   /* check_geom.c */
gtet_status chk_volume(chk_ctx *c);        /* check_geom.c */
gtet_status chk_full(chk_ctx *c);          /* check_geom.c */

/* gtet_check_arrays_opt() (opts NULL: the defaults); with cell not NULL (closed mode) also hands over the Delaunay cells
 * (chk_ctx.cell, .cell_hull; NULL when the check failed), which the caller frees. */
gtet_status chk_check_arrays(const double *vertices, size_t nv, const uint32_t *tets, size_t nt,
                             const uint32_t *neighbors, const double *xyz, size_t n,
                             const gtet_check_options *opts, gtet_check_report *report,
                             uint32_t **cell, uint8_t **cell_hull);

/* The point of pts (n points `stride` bytes apart, each starting with its three doubles)
 * nearest to p in the max norm, when it lies within 1e-5 of p relative to p's largest
 * coordinate: a mesh writer that rounded the coordinates (meshio's ASCII .vtu keeps 12
 * digits, Gmsh's ASCII MSH %.16g) moved the point by about that much, and the messages of
 * check (NOTES.md E157) and diff (E181) say so.  Its index in *best and the distance relative
 * to p's largest coordinate in *rel; 0 when no point is that near.  A linear scan: for a
 * failure's message only (check.c). */
int chk_rounded_match(const void *pts, size_t stride, size_t n, const double p[3], size_t *best,
                      double *rel);

/* The whole checker on a filled context (inputs set, built fields zero); frees what it builds
 * except cell[] and cell_hull[] (the caller's, when want_cells; freed on failure). */
gtet_status chk_run(chk_ctx *c);

#endif
