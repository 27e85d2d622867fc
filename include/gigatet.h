/* gigatet.h -- the one public header of gigatet, a robust 3D Delaunay kernel.
 *
 * gigatet builds the Delaunay tetrahedrization of n points in R^3 by incremental
 * (Bowyer-Watson) insertion along a Moore curve with BRIO rounds.  Every sign it uses comes
 * from two predicates, orient3d and insphere, evaluated exactly for all finite doubles
 * (semi-static filter -> exact expansion / integer stage -> GMP), and exact zeros are broken
 * by a symbolic perturbation that depends only on the points (lexicographic rank, the rule
 * CGAL's Delaunay_triangulation_3 uses).  Hence the output is THE perturbed Delaunay
 * tetrahedrization of the set of distinct input points: independent of input order,
 * insertion order and thread count, and equal to CGAL's tet for tet.
 *
 * Conventions
 *   - Points are given as xyz[3*i+0..2], i < n, finite doubles (NaN/Inf are rejected).
 *   - Exact duplicates (with -0.0 == +0.0) are not vertices: each input point maps to the
 *     vertex of its first occurrence (gtet_mesh_input_map), and the count is reported.
 *   - Mesh vertices are the distinct input points numbered 0..nv-1 in order of first
 *     occurrence.  Tets are 4 vertex ids, positively oriented (orient3d > 0).
 *   - Facet f of a tet is the facet opposite its vertex f; neighbor[4*t+f] is the tet across
 *     it, or GTET_NO_TET on the convex hull.
 *   - The library never prints and never exits; it reports through return codes and the
 *     optional callbacks in gtet_options.
 *
 * Thread safety: every function is reentrant; a gtet_mesh may be read from many threads.
 */
#ifndef GIGATET_H
#define GIGATET_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GTET_VERSION_MAJOR 0
#define GTET_VERSION_MINOR 1
#define GTET_VERSION_PATCH 0

/* GTET_API marks the public functions: exported from libgigatet.so, which is compiled with
 * hidden visibility (-fvisibility=hidden) so that nothing else is; empty for users. */
#if defined(GTET_BUILDING_LIBRARY) && (defined(__GNUC__) || defined(__clang__))
#define GTET_API __attribute__((visibility("default")))
#else
#define GTET_API
#endif

/* The library's version at run time, "MAJOR.MINOR.PATCH" (static string): the macros above
 * say which header a program was compiled with, this which library it runs with. */
GTET_API const char *gtet_version(void);

/* ------------------------------------------------------------------------------------------ */
/* Status                                                                                     */
/* ------------------------------------------------------------------------------------------ */

typedef enum gtet_status {
    GTET_OK = 0,
    GTET_ERR_ARGUMENT = 1,          /* a NULL pointer, an invalid option value */
    GTET_ERR_NONFINITE = 2,         /* a NaN or infinite coordinate (gtet_error.index says where) */
    GTET_ERR_DEGENERATE_INPUT = 3,  /* < 4 distinct points, or all collinear / coplanar */
    GTET_ERR_OUT_OF_MEMORY = 4,     /* an allocation failed, or the run would not fit
                                       (gtet_options.memory_limit); nothing leaked */
    GTET_ERR_TOO_LARGE = 5,         /* more points or tets than the index types hold */
    GTET_ERR_CHECK_FAILED = 6,      /* the exact checker found a violated invariant */
    GTET_ERR_INTERNAL = 7,          /* a broken internal invariant: please report it */
    GTET_ERR_CANCELLED = 8          /* gtet_options.cancel (or gtet_check_options.cancel)
                                       asked to stop; nothing leaked */
} gtet_status;

/* A static, never-NULL English description of a status. */
GTET_API const char *gtet_status_str(gtet_status status);

/* Details of a failure, filled when the caller passes one (see gtet_options.error). */
typedef struct gtet_error {
    gtet_status status;
    size_t index;       /* input index the error is about, or SIZE_MAX */
    int dimension;      /* for GTET_ERR_DEGENERATE_INPUT: affine dimension 0, 1 or 2; else -1 */
    char message[256];  /* one English sentence, NUL-terminated */
} gtet_error;

/* ------------------------------------------------------------------------------------------ */
/* Predicates (exact for all finite doubles, denormals and 2^1000 included)                  */
/* ------------------------------------------------------------------------------------------ */
/* For finite coordinates.  NaN and infinities have no sign: when any coordinate is NaN or
 * infinite, each predicate below returns 0 and computes nothing (it never reaches the exact
 * stages).  gtet_triangulate and gtet_check reject such points (GTET_ERR_NONFINITE); Python's
 * gigatet.orient3d and gigatet.insphere raise ValueError. */

/* Sign of det[b-a; c-a; d-a]: +1 when (a,b,c,d) is positively oriented, as (0, e_x, e_y, e_z)
 * is; -1 for the mirror image; 0 when the four points are coplanar. */
GTET_API int gtet_orient3d(const double a[3], const double b[3], const double c[3],
                           const double d[3]);

/* +1 when e is strictly inside the sphere through a,b,c,d and orient3d(a,b,c,d) > 0; the sign
 * flips with the orientation of (a,b,c,d); 0 when the five points are co-spherical (or
 * a,b,c,d coplanar and e on their circle / plane in the degenerate sense of the determinant). */
GTET_API int gtet_insphere(const double a[3], const double b[3], const double c[3],
                           const double d[3], const double e[3]);

/* As gtet_insphere, with exact zeros broken by the lexicographic symbolic perturbation of
 * Devillers & Teillaud (CGAL's rule): never 0 for five distinct points with
 * orient3d(a,b,c,d) != 0. */
GTET_API int gtet_insphere_sos(const double a[3], const double b[3], const double c[3],
                               const double d[3], const double e[3]);

/* The hull rule.  A ghost (infinite) tet is (a,b,c,infinity), with its finite facet (a,b,c)
 * ordered so that orient3d(a,b,c,p) < 0 for the points p of the hull.  e conflicts with it
 * (+1) when orient3d(a,b,c,e) > 0, i.e. e is strictly beyond the hull facet; when e is
 * coplanar with (a,b,c), +1 when e is inside the perturbed circle through a,b,c (CGAL's
 * coplanar_side_of_bounded_circle with perturbation), else -1.  Never 0 for four distinct
 * points with a,b,c not collinear. */
GTET_API int gtet_ghost_conflict(const double a[3], const double b[3], const double c[3],
                                 const double e[3]);

/* Counters of how each predicate call on this thread was decided.  The public predicates
 * above count into a thread-local record; the kernel counts per worker thread and reports the
 * sum in gtet_stats. */
typedef struct gtet_pred_counters {
    uint64_t orient_calls;      /* orient3d evaluations */
    uint64_t orient_exact;      /* ... that the filter could not decide */
    uint64_t orient_int;        /* ... decided by an exact integer stage (small integers, or
                                   the 60-bit integer form of the tuple) */
    uint64_t orient_gmp;        /* ... that needed the GMP (out-of-range) exact stage */
    uint64_t orient_zero;       /* ... that were exactly zero */
    uint64_t insphere_calls;    /* insphere evaluations */
    uint64_t insphere_exact;    /* ... that the filter could not decide */
    uint64_t insphere_int;      /* ... decided by an exact integer stage (small integers, or
                                   the 60-bit integer form of the tuple) */
    uint64_t insphere_gmp;      /* ... that needed the GMP exact stage */
    uint64_t insphere_zero;     /* ... that were exactly zero */
    uint64_t sos_calls;         /* symbolic perturbation decisions (insphere and hull rule) */
    uint64_t sos_depth[4];      /* ... decided at perturbation term 1, 2, 3, 4 (insphere uses
                                   terms 1-2, the coplanar circle rule 1-4) */
    uint64_t insphere_int122;   /* of insphere_int: decided by the 122-bit integer form (tuples
                                   spanning 61-122 binades, which went to GMP before) */
} gtet_pred_counters;

/* Copy the calling thread's counters; reset them. */
GTET_API void gtet_pred_counters_get(gtet_pred_counters *out);
GTET_API void gtet_pred_counters_reset(void);

/* ------------------------------------------------------------------------------------------ */
/* Triangulation                                                                              */
/* ------------------------------------------------------------------------------------------ */

typedef struct gtet_mesh gtet_mesh;

#define GTET_NO_TET UINT32_MAX

typedef struct gtet_options {
    int threads;        /* worker threads; 0 = all cores (default 0); at most 255 are used,
                           and at most as many as OpenMP gives a region started by the calling
                           thread (OMP_THREAD_LIMIT; 1 inside a parallel region with nesting
                           off) and the system lets the process start (ulimit -u): the tets
                           are the same, gtet_stats.threads says how many ran.  dyn-var
                           (OMP_DYNAMIC) is off during the call and restored after it */
    int verbosity;      /* 0 silent; 1: one line per phase (validate, sort, insert, finalize,
                           check) with its seconds; 2: also one per BRIO round (points,
                           inserted, passes, threads, alpha of the first pass, seconds);
                           messages go to message() */
    int check;          /* nonzero: run the exact checker on the result; a failure returns
                           GTET_ERR_CHECK_FAILED and no mesh */
    /* Called now and then with the fraction of points inserted, from the calling thread. */
    void (*progress)(void *user, double fraction);
    void *progress_user;
    /* Called with one NUL-terminated line per message (verbosity > 0), from the calling
     * thread, outside any parallel region; the line is valid during the call only. */
    void (*message)(void *user, const char *line);
    void *message_user;
    /* When not NULL, filled with the details of any failure. */
    gtet_error *error;
    /* Nonzero: record every decision of the symbolic perturbation (gtet_mesh_degeneracies);
     * default 0.  Costs nothing when off. */
    int degeneracies;
    /* Records stored at most when recording (their total count stays exact); default 100000. */
    size_t degeneracy_limit;
    /* When not NULL, polled on the calling thread (outside the parallel regions) before each
     * BRIO round, before each parallel pass of a round and every 65536 points of a pass on
     * one thread, and with check during the check as gtet_check_options.cancel is (below); a
     * nonzero return stops the run: GTET_ERR_CANCELLED, no mesh.  (The Python module turns
     * Ctrl-C into KeyboardInterrupt through it.) */
    int (*cancel)(void *user);
    void *cancel_user;
    /* The memory guard.  Before any big allocation gtet_triangulate estimates the run's peak
     * (gtet_estimate_memory) and, when it cannot fit, returns GTET_ERR_OUT_OF_MEMORY at once
     * with a message such as "out of memory: needs about 23.4 GiB, 20.1 GiB available
     * (MemAvailable)" naming the limit that bound it -- instead of a process the kernel's OOM
     * killer ends later (Linux overcommits: malloc rarely fails).
     *   0 (default): against what the machine can give: the smallest of MemAvailable
     *      (/proc/meminfo), the memory cgroup's limit less its working set (v2 memory.max,
     *      v1 memory.limit_in_bytes, the process's cgroup and its ancestors), and, for the
     *      address space the run maps, RLIMIT_AS / RLIMIT_DATA less what is mapped already;
     *   SIZE_MAX: no guard (allocation failures still return GTET_ERR_OUT_OF_MEMORY);
     *   any other value: that many bytes are available, whatever the machine says. */
    size_t memory_limit;
    /* When not NULL, called once, from the calling thread, as soon as the run has no further
     * use for xyz: after the validate stage has copied the distinct points into the mesh's
     * vertices, or, with opts.check, after the check (which compares the mesh with xyz).  The
     * caller may free or reuse its array from then on; the library neither reads it again nor
     * frees it.  A run that fails before that point does not call it.  For a caller whose input
     * array is its own (the CLI frees the points it read, 24 bytes a point: 1.8 GiB at 80M, at
     * the insertion's peak).  With it set, the memory guard counts those 24 bytes a point as
     * available for the run's peak, which comes after it; gtet_estimate_memory never counts
     * the caller's array. */
    void (*input_done)(void *user);
    void *input_done_user;
} gtet_options;

/* Fill *opts with the defaults above.  Fields are only ever added at the end of
 * gtet_options; initialise it with this function, then set what differs. */
GTET_API void gtet_options_init(gtet_options *opts);

/* The peak memory, in bytes, gtet_triangulate is estimated to need for n points with these
 * options (NULL: the defaults): the pages it touches at its peak -- the insertion (the
 * working mesh, 32 bytes per tet slot and about 7 slots per point, plus the kernel's
 * per-point arrays, more with several threads), the compaction that follows it, or the exact
 * check when opts->check -- and a few MiB fixed; with one thread about 280 bytes a point,
 * with two 290, with the check 690.  It counts every array the library allocates, not the
 * caller's input array (24 bytes a point) nor anything else the caller holds.  Calibrated
 * against measured peaks (uniform, jittered, clustered, grid, sphere, heavy-tailed points,
 * 1-2 threads, 100k-10M): never more than a few percent below them.  Inputs with many more
 * tets per point than 7 (points on one sphere or paraboloid: 15-22) need up to 3x more. */
GTET_API size_t gtet_estimate_memory(size_t n, const gtet_options *opts);

/* The guard gtet_triangulate runs first, on its own: GTET_OK when a run of n points with
 * these options (NULL: the defaults) fits under opts->memory_limit's rule, else
 * GTET_ERR_OUT_OF_MEMORY with opts->error (if given) saying why.  For a caller that will run
 * gtet_check itself after gtet_triangulate: ask with opts->check set, before the work. */
GTET_API gtet_status gtet_memory_guard(size_t n, const gtet_options *opts);

/* Build the Delaunay tetrahedrization of the n points xyz[3*i..3*i+2].  On success *mesh
 * holds the result (free it with gtet_mesh_free); on failure *mesh is NULL, the status says
 * why and opts->error (if given) the details.  opts may be NULL for the defaults. */
GTET_API gtet_status gtet_triangulate(const double *xyz, size_t n, const gtet_options *opts,
                                      gtet_mesh **mesh);

GTET_API void gtet_mesh_free(gtet_mesh **mesh);  /* sets *mesh to NULL; NULL-safe */

GTET_API size_t gtet_mesh_num_points(const gtet_mesh *mesh);      /* n as given */
GTET_API size_t gtet_mesh_num_vertices(const gtet_mesh *mesh);    /* distinct points */
GTET_API size_t gtet_mesh_num_duplicates(const gtet_mesh *mesh);  /* n - vertices */
GTET_API size_t gtet_mesh_num_tets(const gtet_mesh *mesh);        /* finite tets */
GTET_API size_t gtet_mesh_num_hull_facets(const gtet_mesh *mesh);

/* 3*nv coordinates of the vertices. */
GTET_API const double *gtet_mesh_vertices(const gtet_mesh *mesh);
/* n entries: the vertex id of input point i (the first occurrence for a duplicate). */
GTET_API const uint32_t *gtet_mesh_input_map(const gtet_mesh *mesh);
/* 4*nt vertex ids, each tet positively oriented. */
GTET_API const uint32_t *gtet_mesh_tets(const gtet_mesh *mesh);
/* 4*nt tet ids: neighbor[4*t+f] is across the facet opposite tets[4*t+f], or GTET_NO_TET. */
GTET_API const uint32_t *gtet_mesh_neighbors(const gtet_mesh *mesh);

/* One decision of the symbolic perturbation during gtet_triangulate (opts.degeneracies): an
 * exact zero the kernel met and the sign the perturbation gave it.  Vertex ids are mesh ids
 * (gtet_mesh_vertices), in the predicate's argument order, so that, with v_i the coordinates
 * of vertex[i],
 *   GTET_DEGENERACY_COSPHERICAL: gtet_insphere(v0, v1, v2, v3, v4) == 0 (five co-spherical
 *     points; v0..v3 is a tet of the mesh under construction, gtet_orient3d > 0) and
 *     sign == gtet_insphere_sos(v0, v1, v2, v3, v4): +1 when v4 conflicts with that tet;
 *   GTET_DEGENERACY_COPLANAR (the hull rule): v3 lies in the plane of the hull facet
 *     (v0, v1, v2) and on its circumcircle (gtet_orient3d(v0, v1, v2, v3) == 0, and
 *     gtet_insphere(v0, v1, v2, v3, x) == 0 for every x), and sign ==
 *     gtet_ghost_conflict(v0, v1, v2, v3): +1 when v3 is inside the perturbed circle (it
 *     conflicts with the ghost tet on that facet); vertex[4] is GTET_NO_VERTEX.
 * term: the term of the perturbation's expansion that decided, 1..4 (the one counted in
 * gtet_pred_counters.sos_depth[term-1]; insphere uses 1-2, and 3 only if v0..v3 were flat). */
#define GTET_NO_VERTEX UINT32_MAX
typedef enum gtet_degeneracy_kind {
    GTET_DEGENERACY_COSPHERICAL = 1,   /* insphere == 0: five points, one sphere */
    GTET_DEGENERACY_COPLANAR = 2       /* hull rule: a point on a hull facet's circle */
} gtet_degeneracy_kind;
typedef struct gtet_degeneracy {
    int kind;               /* gtet_degeneracy_kind */
    int npoints;            /* 5 (co-spherical) or 4 (coplanar) */
    uint32_t vertex[5];     /* mesh vertex ids, argument order; unused entries GTET_NO_VERTEX */
    int term;               /* 1..4 */
    int sign;               /* +1 or -1: the perturbed predicate's value */
} gtet_degeneracy;

/* The decisions recorded when the mesh was built with opts.degeneracies (else NULL, and 0
 * in both counts).  *total (may be NULL) receives how many decisions the run made: it equals
 * gtet_stats.pred.sos_calls, and as many have term k as sos_depth[k-1] says.  The returned
 * array, owned by the mesh, holds *stored (may be NULL) = min(total, opts.degeneracy_limit)
 * of them, sorted by kind, then vertex ids in order, then term and sign (a tuple the kernel
 * tested twice appears twice).  With one thread the run is deterministic, and so is the list.
 * With several, which insertions are tried, deferred and retried depends on the schedule, so
 * the decisions (tuples and counts) can differ from run to run while the mesh never does; the
 * order depends only on the set of records.  Truncated, the list keeps each thread's first
 * `limit` decisions (each thread records in its own order) and then the smallest in the
 * order above. */
GTET_API const gtet_degeneracy *gtet_mesh_degeneracies(const gtet_mesh *mesh, size_t *stored,
                                                       uint64_t *total);

/* Per-round record of the parallel insertion. */
typedef struct gtet_round_stats {
    uint64_t points;      /* points of this round */
    uint64_t tried;       /* insertion attempts (retries included; points a thread passed
                             over after giving up on its slice are not attempts) */
    uint64_t inserted;    /* points inserted */
    uint64_t deferred;    /* attempts rolled back: a tet of another thread on the way (or the
                             walk's step budget, or no slot left in the pass) */
    int threads;          /* the most threads a pass of the round used */
    int passes;           /* partition passes the round needed */
    double alpha_first;   /* success rate alpha of the round's first pass: inserted / points
                             (paper section 4.2; it picks the next pass's policy); 1 when the
                             round was inserted serially */
    int ownership;        /* vertices of a thread's colour that made a tet its own in the
                             round's last parallel pass: 4 (all, the default), 3 (after the
                             run's first failed pass, proofs/parallel.md), 0 if none ran */
    uint64_t rebalanced;  /* points of the round's first pass that the threads had not tried
                             when one of them finished its slice, and that were cut between
                             neighbouring threads instead (0: no rebalancing) */
} gtet_round_stats;

typedef struct gtet_stats {
    gtet_pred_counters pred;    /* summed over the worker threads */
    double seconds_validate;    /* duplicate detection and dimension check */
    double seconds_sort;        /* Moore keys, radix sort, BRIO */
    double seconds_insert;      /* incremental insertion */
    double seconds_finalize;    /* compaction, orientation of the output */
    double seconds_total;
    uint64_t tets_created;      /* tets written by cavities, ghosts included */
    uint64_t walk_steps;        /* visibility-walk steps */
    uint64_t walk_fallbacks;    /* walks that ran out of steps and fell back to a linear scan
                                   (never expected: proofs/termination.md T1.4) */
    size_t bytes_per_tet;       /* the mesh arrays' bytes per tet (struct of arrays) */
    size_t peak_bytes;          /* the kernel's own peak allocation */
    int threads;                /* threads used */
    int num_rounds;             /* BRIO rounds */
    const gtet_round_stats *rounds;  /* num_rounds records, owned by the mesh */
} gtet_stats;

/* Statistics of the run that built the mesh. */
GTET_API void gtet_mesh_stats(const gtet_mesh *mesh, gtet_stats *stats);

/* ------------------------------------------------------------------------------------------ */
/* Exact invariant checker                                                                    */
/* ------------------------------------------------------------------------------------------ */

enum {
    GTET_CHECK_FULL = 1u << 0,      /* add the O(n*m) empty-sphere test (small meshes only) */
    GTET_CHECK_NO_FILTER = 1u << 1, /* every sign from the GMP oracle, without the checker's
                                       interval filter (slower; cross-checks the filter) */
    GTET_CHECK_DELAUNAY = 1u << 2,  /* judge the Delaunay property itself, ties allowed (any
                                       tool's Delaunay mesh passes), instead of the canonical
                                       perturbed triangulation gigatet and CGAL build */
    GTET_CHECK_ANY_ORIENTATION = 1u << 3  /* accept negatively oriented tets (counted in the
                                             report); a flat tet still fails */
};

/* The first violated invariant, in a form a program can read (the report's message says the
 * same in English).  Unused entries are GTET_CHECK_NONE (tet) or absent (nvertices). */
#define GTET_CHECK_NONE UINT64_MAX
typedef struct gtet_check_violation {
    const char *stage;      /* NULL when every invariant holds; else the checker stage that
                               failed, a stable identifier: "arguments", "vertices", "input",
                               "orientation", "facets", "neighbors", "hull_surface", "links",
                               "euler", "delaunay", "hull", "volume", "full"; or
                               "cancelled" (gtet_check_options.cancel stopped it) */
    uint64_t tet[2];        /* the tets involved (mesh order), or GTET_CHECK_NONE */
    int nvertices;          /* 0..5: the vertices involved, with their coordinates */
    uint32_t vertex[5];
    double point[5][3];
    int tie;                /* 1 when the failed test was exactly degenerate (co-spherical, or
                               coplanar on the hull) and only the canonical rule rejects it:
                               the mesh breaks a tie differently from the symbolic
                               perturbation; GTET_CHECK_DELAUNAY accepts such ties */
    uint64_t group_size;    /* for a tie: the mesh vertices on that sphere (or hull plane) */
} gtet_check_violation;

typedef struct gtet_check_report {
    int ok;                     /* 1 when every invariant holds */
    unsigned mode;              /* GTET_CHECK_DELAUNAY when the closed Delaunay property was
                                   judged, 0 for the canonical (perturbed) triangulation */
    uint64_t tets;              /* finite tets checked */
    uint64_t facets_checked;    /* facets whose local Delaunay property was tested */
    uint64_t hull_facets;
    uint64_t duplicates;        /* input points that matched an earlier point */
    uint64_t negative_tets;     /* tets accepted though negatively oriented
                                   (GTET_CHECK_ANY_ORIENTATION) */
    uint64_t unused_vertices;   /* mesh vertices in no tet, each a copy of a vertex that is in
                                   one (tools that keep duplicate input points write these) */
    uint64_t cospherical_facets;  /* interior facets whose two tets' five vertices are
                                     co-spherical (ties; counted in GTET_CHECK_DELAUNAY mode) */
    uint64_t coplanar_hull_edges; /* hull edges whose two hull facets are coplanar (ditto) */
    int euler;                  /* V - E + F - T of the finite complex (1 for a ball) */
    gtet_check_violation violation;  /* the first violation (stage NULL when ok) */
    char message[512];          /* first violation found, or a summary */
} gtet_check_report;

/* Check a mesh against the points it was built from (xyz may be NULL: then the vertex set is
 * not compared with the input).  Uses an independent exact GMP implementation of every
 * predicate.  Returns GTET_OK or GTET_ERR_CHECK_FAILED (or an allocation / argument error;
 * GTET_ERR_CANCELLED only through gtet_check_opt's cancel, below);
 * report may be NULL.  Runs on OpenMP's default thread count (OMP_NUM_THREADS), or on as many
 * threads as the process can start when that is fewer (the same verdict either way). */
GTET_API gtet_status gtet_check(const gtet_mesh *mesh, const double *xyz, size_t n, unsigned flags,
                                gtet_check_report *report);

/* The same checker on plain arrays, e.g. a mesh read from a file or built by another tool.
 * neighbors may be NULL (then adjacency is rebuilt and only its consistency is checked).
 *
 * Modes (flags):
 *   0 (canonical): the mesh must be THE perturbed Delaunay tetrahedrization, the unique one
 *     gigatet and CGAL build: every interior facet locally Delaunay for the symbolically
 *     perturbed insphere, the hull convex under the perturbed hull rule.  On degenerate input
 *     another tool's correct Delaunay mesh can fail it; the failure then says it is a tie
 *     (violation.tie, with the size of the co-spherical or coplanar group).
 *   GTET_CHECK_DELAUNAY: the Delaunay property itself, ties allowed: every interior facet
 *     locally Delaunay in the closed sense (the apex across it not strictly inside the tet's
 *     circumsphere), the hull weakly convex.  With the structural stages this proves that no
 *     vertex is strictly inside any tet's circumsphere (the Delaunay lemma, src/check/check.c).
 *   GTET_CHECK_ANY_ORIENTATION (either mode): negatively oriented tets are counted
 *     (report.negative_tets) and judged as their mirror image; a flat tet still fails.
 * Both modes check every structural invariant: vertex ids, distinct finite vertices, the
 * vertex set against xyz (matched by coordinates: the mesh may number its vertices in any
 * order; a vertex in no tet is accepted when it repeats the point of one that is in a tet, as
 * tools that keep duplicate input points write them), facets in one or two tets on opposite
 * sides, a closed hull surface, vertex links that are spheres or disks, V - E + F - T = 1,
 * the exact volume. */
GTET_API gtet_status gtet_check_arrays(const double *vertices, size_t nv, const uint32_t *tets,
                                       size_t nt, const uint32_t *neighbors, const double *xyz,
                                       size_t n, unsigned flags, gtet_check_report *report);

/* The checker with options (gtet_check and gtet_check_arrays are these with flags only), for
 * a caller that wants to stop a long check.  Fields are only ever added at the end; initialise
 * with gtet_check_options_init, then set what differs. */
typedef struct gtet_check_options {
    unsigned flags;     /* GTET_CHECK_* as above; default 0 */
    /* When not NULL, polled on the calling thread only: before each stage and inside the long
     * loops (every 1024 items of its share; in the full test every 1024 points against a
     * tet), milliseconds apart; the other threads read a shared flag at every item.  A nonzero
     * return stops the check: GTET_ERR_CANCELLED, report->ok 0, violation.stage "cancelled",
     * the message names the stage; no verdict, nothing leaked.  Never stopping, it changes no
     * verdict nor report.  Costs nothing when NULL.  (Python's Ctrl-C goes through it.) */
    int (*cancel)(void *user);
    void *cancel_user;
} gtet_check_options;

/* Fill *opts with the defaults above (flags 0, no cancel). */
GTET_API void gtet_check_options_init(gtet_check_options *opts);

/* gtet_check and gtet_check_arrays with options (opts NULL: the defaults). */
GTET_API gtet_status gtet_check_opt(const gtet_mesh *mesh, const double *xyz, size_t n,
                                    const gtet_check_options *opts, gtet_check_report *report);
GTET_API gtet_status gtet_check_arrays_opt(const double *vertices, size_t nv,
                                           const uint32_t *tets, size_t nt,
                                           const uint32_t *neighbors, const double *xyz,
                                           size_t n, const gtet_check_options *opts,
                                           gtet_check_report *report);

/* ------------------------------------------------------------------------------------------ */
/* Comparing two meshes of one point set                                                      */
/* ------------------------------------------------------------------------------------------ */

typedef enum gtet_diff_kind {
    GTET_DIFF_IDENTICAL = 0,        /* the same set of tets over the same points */
    GTET_DIFF_TIES = 1,             /* both are Delaunay (closed sense) and differ only in how
                                       they triangulate co-spherical groups (the groups) */
    GTET_DIFF_A_NOT_DELAUNAY = 2,   /* A fails the closed Delaunay check (check_a says how) */
    GTET_DIFF_B_NOT_DELAUNAY = 3,   /* B fails it (check_b) */
    GTET_DIFF_NEITHER_DELAUNAY = 4, /* both fail it */
    GTET_DIFF_POINTS = 5            /* their vertex sets differ (or differ from xyz) */
} gtet_diff_kind;

/* One co-spherical group: the vertices of one cell of the Delaunay subdivision (all on one
 * empty sphere, >= 5 of them) that A and B triangulate differently. */
typedef struct gtet_diff_group {
    uint64_t size;          /* points in the group */
    uint64_t tets_a;        /* A's tets in the group, of which */
    uint64_t only_a;        /* ... this many are not tets of B */
    uint64_t tets_b, only_b;
    int on_hull;            /* 1 when the group has a facet on the convex hull (a coplanar hull
                               face whose triangulation may be what differs) */
    double point[3];        /* the group's lexicographically smallest point */
    double center[3];       /* its sphere's centre, rounded (for orientation only) */
} gtet_diff_group;

typedef struct gtet_diff_report {
    gtet_diff_kind kind;
    uint64_t tets_a, tets_b;
    uint64_t common;            /* tets in both (same four points) */
    uint64_t only_a, only_b;    /* tets in one mesh only */
    uint64_t points_only_a, points_only_b;  /* distinct points in one mesh only (kind POINTS) */
    double first_point_only[3]; /* one of them (kind POINTS) */
    gtet_check_report check_a, check_b;  /* the closed Delaunay checks (when they ran) */
    uint64_t num_groups;        /* co-spherical groups where A and B differ (kind TIES) */
    gtet_diff_group *groups;    /* all of them, sorted by their point; malloc'ed, freed by
                                   gtet_diff_report_free */
    char message[512];          /* one sentence: the verdict */
} gtet_diff_report;

/* Compare two meshes of one point set as sets of tets over coordinates: numbering, vertex
 * order and orientation inside each tet may differ.  When they differ, both are checked in
 * GTET_CHECK_DELAUNAY | GTET_CHECK_ANY_ORIENTATION mode (against xyz when given), and when
 * both pass, the tets that differ are grouped by the Delaunay cell they triangulate.  When
 * they are identical and xyz is given, the mesh is checked once the same way against xyz: a
 * failure is GTET_DIFF_NEITHER_DELAUNAY (check_a and check_b say why), not IDENTICAL.  Returns
 * GTET_OK when the comparison ran (report.kind says the verdict), or an argument / memory
 * error.  Free the report's groups with gtet_diff_report_free. */
GTET_API gtet_status gtet_diff(const double *va, size_t nva, const uint32_t *ta, size_t nta,
                               const double *vb, size_t nvb, const uint32_t *tb, size_t ntb,
                               const double *xyz, size_t n, gtet_diff_report *report);
GTET_API void gtet_diff_report_free(gtet_diff_report *report);

#ifdef __cplusplus
}
#endif
#endif /* GIGATET_H */
