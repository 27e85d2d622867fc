/* mpi_internal.h -- shared pieces of gigatet's distributed mode (src/mpi/), not public.
 * Built on the public API (gigatet.h) and MPI, and one internal hook: mpi_patch.c takes the
 * first round's tet arrays from its gtet_mesh (gtet_mesh_take_arrays, mesh/mesh.h) to patch
 * them in place. */
#ifndef GTET_MPI_INTERNAL_H
#define GTET_MPI_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "gigatet.h"

#include "gigatet_mpi.h"

/* A point with its global vertex id (or, before the ids exist, its global input index). */
typedef struct mpt {
    double x[3];
    uint64_t id;
} mpt;

/* One rank's view of a collective run. */
typedef struct mctx {
    MPI_Comm comm;
    int rank, size;
    gtet_error err;          /* this rank's error, then the agreed one */
    gtet_mpi_stats *st;
    int *sc, *sd, *rc, *rd;  /* 4 * size ints for the all-to-all exchanges */
} mctx;

/* Allocation with an optional injected failure (tests only): see gtet_mpi_debug_fail_alloc. */
void *mx_malloc(size_t bytes);
void *mx_calloc(size_t count, size_t size);
void *mx_realloc(void *p, size_t bytes);

/* Fault injection for the tests: on this process, the `after`-th allocation of the
 * distributed layer from now on fails (0 = the next one; negative = never).  Not thread-safe;
 * the distributed layer allocates from the calling thread only. */
void gtet_mpi_debug_fail_alloc(long after);

/* Set this rank's error (first one wins); returns status. */
gtet_status mx_fail(mctx *c, gtet_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Collective: agree on a status.  Returns GTET_OK when every rank passed GTET_OK, else the
 * error of the lowest failing rank, whose gtet_error is copied to every rank's c->err. */
gtet_status mx_agree(mctx *c, gtet_status mine);

/* Collective all-to-all of records of `rsize` bytes: scnt[q] records to rank q, sent from
 * sbuf in rank order.  On success *rbuf (malloc'ed, never NULL) holds rcnt[q] records from
 * each q in rank order, *rtot in all.  Errors (counts over INT_MAX, allocation) are agreed
 * on.  `ghost`: count the bytes as ghost traffic too. */
gtet_status mx_exchange(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                        void **rbuf, size_t *rcnt, size_t *rtot, int ghost);

/* mx_exchange where sbuf holds no records for this rank: the caller writes its scnt[rank]
 * records into *rbuf itself, from record rcnt[0] + ... + rcnt[rank - 1] on (the partition: a
 * rank's own points go straight into its tile, NOTES.md E223) */
gtet_status mx_exchange_keep(mctx *c, const void *sbuf, const size_t *scnt, size_t rsize,
                             void **rbuf, size_t *rcnt, size_t *rtot, int ghost);

double mx_now(void);
/* vzeroupper where the CPU has AVX, before the MPI layer's floating-point loops (mpi_util.c) */
void mx_upper_clean(void);

/* The written whole pages of [from, from + fbytes) moved, in address order, onto the pages of
 * [to, to + tbytes) never written (mremap; fresh zero pages mapped where they were), so that
 * writing `to` takes no fresh memory (mpi_pages.c, NOTES.md E221).  Both ranges wholly the
 * caller's and inside blocks it owns (the allocator's own words lie outside them); afterwards
 * `from` holds zeros or its old bytes page by page and the moved pages of `to` from's old bytes:
 * for an array that is dead and one about to be overwritten.  The pages moved; 0 where the
 * system cannot (nothing changed, or `to` partly moved); -1 when `from` could not be mapped
 * again (its block must not be used, nor freed). */
long mx_pages_move(void *from, size_t fbytes, void *to, size_t tbytes);

/* a test switch from the environment: -1 for "off" or "0", 1 for "on" or "1", else 0 */
int mx_env_mode(const char *name);

/* gtet_options.input_done for a local triangulation's own copy of its points: user is the
 * address of the double * to free (and set to NULL).  The kernel calls it once it has copied
 * the points (src/api/triangulate.c), so its later arrays can take that block instead of fresh
 * memory (NOTES.md Q14, E122); the caller frees the pointer after the run too (NULL-safe). */
void mx_free_input(void *user);

/* A local triangulation of n distinct points (the kernel's duplicate pass skipped; arrays with
 * room for the output's 64-bit rows: src/mesh/mesh.h gtet_triangulate_wide_distinct) with the
 * rank's options lopt, errors in *e.  xyz is the run's own copy: freed here, as soon as the
 * kernel has copied it (mx_free_input). */
gtet_status mx_triangulate_own(const gtet_options *lopt, double *xyz, size_t n, gtet_mesh **out,
                               gtet_error *e);

/* MPI_Wait on rq, sleeping between tests once it has waited ~20 us (mpi_util.c) */
void mx_wait(MPI_Request *rq);

/* the send order of n records bound for ranks dst[i] (a stable counting sort): perm[k] = the
 * record sent k-th; scnt[q] (zeroed by the caller) gets the count for rank q; pos: P + 1
 * entries of scratch */
void mx_rank_order(const int *dst, size_t n, int P, size_t *scnt, size_t *pos, size_t *perm);

/* max(a, b), a NaN in either giving NaN: inlined where the C library's fmax is a call (1.4 %
 * of a rank's instructions, from the ball and box tests of every star tet); the callers'
 * values are finite, and a NaN would only make their tests conservative */
static inline double mx_max(double a, double b)
{
    return (a > b || isnan(a)) ? a : b;
}

/* the floating distance from x to a box (lo[3], hi[3]); 0 inside */
double mx_box_dist(const double *box, const double *x);

/* qsort of n elements; nothing at all for n < 2, so an empty array may be NULL (the C library's
 * qsort requires a valid pointer even for n == 0). */
static inline void mpi_sort(void *p, size_t n, size_t size, int (*cmp)(const void *, const void *))
{
    if (n > 1) qsort(p, n, size, cmp);
}

/* ------------------------------------------------------------------------------------------ */
/* gtet_triangulate_mpi's run, shared by its steps (mpi_ids.c, mpi_partition.c, mpi_ghosts.c,  */
/* mpi_query.c, mpi_output.c; the entry in mpi_triangulate.c)                                 */
/* ------------------------------------------------------------------------------------------ */

#define NOID UINT64_MAX

/* open-addressing set of uint64 keys (NOID is the empty slot) */
typedef struct hset {
    uint64_t *k;
    size_t cap, n;
} hset;

/* growable byte vector of fixed-size records */
typedef struct vec {
    unsigned char *p;
    size_t n, cap, rs;
} vec;

typedef struct grid {
    double lo[3], hi[3], inv[3];
    int g[3];
    int b[3];                   /* blocks of GB^3 cells, for halfspace queries */
    uint32_t *start;            /* cells + 1: cell ci holds S's tile points start[ci] ..
                                   start[ci + 1] - 1 (the tile is stored in cell order) */
    float *cb;                  /* per cell: its points' bounding box lo[3], hi[3], rounded
                                   outward (a ball's answer skips the cells it misses) */
    float *bb;                  /* per block of GB^3 cells: the union of its cells' cb (a
                                   query's answer skips the blocks it misses, NOTES.md E203) */
    float *pyr;                 /* the block boxes' pyramid: level 0 the blocks' boxes (bb),
                                   level l + 1 each node the union of its 2^3 children at
                                   level l, up to one node (grid_pyramid) */
    size_t poff[24];            /* level l's boxes start at pyr + poff[l] */
    int pdim[24][3], nlev;      /* level l's nodes per axis; the number of levels */
    uint32_t *sat;              /* (g0 + 1)(g1 + 1)(g2 + 1): the cells' point counts summed
                                   below each corner, for the answers' gate (mpi_lift.c) */
    uint64_t *far;              /* a bit per tile point (S's index < m): set when no tet of
                                   DT(S) at it can reach another tile's box (mx_grid_far, D11);
                                   bits, as the queries read them at random (E226) */
} grid;
#define GB 4

typedef struct run {
    mctx c;
    gtet_options lopt;          /* the local triangulations' options */
    const double *xyz;
    size_t n;
    uint64_t first, N;
    uint64_t *firsts_all;       /* 2 per rank: first index, count */
    uint64_t *imap;
    mpt *fp;                    /* this rank's first occurrences (distinct), id = vertex id */
    size_t nf;
    uint64_t V;
    mpt seed[4];                /* smallest affinely independent simplex */
    int seed_rank[4];           /* the tile each seed lives in */
    /* kd tree */
    struct kdn { int axis, left, right, leaf; double split; } *kd;
    int nkd;
    /* tile and the tiles' boxes */
    mpt *tile;                  /* from the partition until mx_grid_build moves it into S */
    size_t m;
    double *box;                /* 6 per rank: lo, hi */
    uint64_t *tcount;           /* per rank */
    double layer;               /* the seeded layer's width in tile spacings */
    /* the local set S: tile points first, then ghosts */
    mpt *sp;
    int *sown;
    size_t ns, scap;
    hset have;                  /* vertex ids of S's ghosts (S's tile points: s_add) */
    hset sent;                  /* tile index * P + rank: sent to that rank */
    uint64_t *sent_any;         /* a bit per tile index: sent to some rank (mx_sent) */
    size_t *nsent;              /* per rank: the tile points sent to it (mx_mark_sent); when
                                   all m were, every answer to it is empty (D12) */
    grid gr;
    gtet_mesh *mesh;            /* the first round's local triangulation DT(S) ... */
    uint32_t *ptv, *ptn;        /* ... or, once patched (mx_patch), DT(S) as 4 vertex ids and */
    size_t pnt;                 /* 4 neighbour tets (GTET_NO_TET on the hull) per tet: the
                                   first round's arrays, taken from R->mesh
                                   (gtet_mesh_take_arrays) and patched in place
                                   (mpi_patch.c: merge, NOTES E80) */
    size_t pcap;                /* tets ptv and ptn have room for, each keeping room for
                                   8 * (4 * pcap + 1) bytes: the output's 64-bit rows
                                   where they lie (gtet_triangulate_wide, E130) */
    size_t qfrom;               /* the local tets this round made start here: the earlier
                                   ones were decided (queried or certified) before (D3) */
    /* keys of the previous round's queried tets / hull facets, sorted */
    uint64_t (*prev)[4];
    size_t nprev;
    int ids32;                  /* gtet_mpi_options.id_bits == 32: the output narrows the
                                   rows where they lie when the global counts fit */
} run;

typedef struct ball {
    double c[3], r;   /* every point of the exact closed circumball is within r of c */
    int all;          /* ill-conditioned or out of range: assume it meets everything */
} ball;

/* a conflict query: a tet (4 points, positively oriented) or a hull facet (3 points in
 * ghost order, id[3] == NOID) */
typedef struct query {
    double p[4][3];
    uint64_t id[4];
} query;

/* containers (mpi_util.c) */
/* splitmix64's finaliser; inline: the dedup, the hash sets and the patch's facet map call it
 * for every record (NOTES.md E135) */
static inline uint64_t mx_mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
int mx_hs_grow(hset *h, size_t cap);          /* 0, or -1 out of memory */
int mx_hs_add(hset *h, uint64_t key);         /* 1 inserted, 0 present, -1 out of memory */
int mx_hs_has(const hset *h, uint64_t key);
void *mx_vec_push(vec *v);                    /* room for one more record, or NULL */

/* the rank (tile) of point x in the partition's kd tree (mpi_partition.c) */
int mx_kd_rank(const run *R, const double *x);

/* the steps, in order; each returns this rank's status (the caller agrees on it) */
gtet_status mx_step_validate(run *R);                     /* 1: ranges, NaN/Inf */
gtet_status mx_step_partition(run *R);                    /* 4: kd tiles, R->tile, boxes (of
                                                             R->fp or, first, of R->xyz) */
gtet_status mx_step_distinct(run *R, int *dups);          /* 2: no duplicate in any tile:
                                                             ids = input indices (D1) */
gtet_status mx_step_dedup(run *R);                        /* 2: duplicates, vertex ids (D1) */
gtet_status mx_step_dimension(run *R);                    /* 3: R->seed of the tiles, or
                                                             degenerate */
gtet_status mx_step_seed(run *R, double layer);           /* 5: S = tile + seeded ghosts */
gtet_status mx_step_rounds(run *R);                       /* 6: rounds until no new point */
gtet_status mx_step_output(run *R, gtet_mpi_result *res); /* 7: owned tets, neighbours */

/* query geometry and answers (mpi_query.c, proofs/distributed.md D4) */
void mx_tet_ball(const double *a, const double *b, const double *cc, const double *d, ball *B);
/* does the conservative ball meet the box (lo[3], hi[3])?  Inlined: the answers call it for
 * every cell a ball's range covers (mpi_query.c, NOTES E81) */
static inline int mx_ball_meets_box(const ball *B, const double *box)
{
    if (B->all) return 1;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = mx_max(box[k] - B->c[k], mx_max(0.0, B->c[k] - box[3 + k]));
        d2 += e * e;
    }
    return sqrt(d2) <= B->r * (1 + 1e-9);
}
/* a ball's reach per axis inside the box (lo[3], hi[3]): every point of the box within the
 * ball has |x_k - c_k| <= h[k] (mpi_query.c, NOTES E132) */
void mx_ball_reach(const double *lo, const double *hi, const ball *B, double h[3]);
/* exact: does the closed halfspace {orient3d(a,b,c,x) >= 0} meet the box? */
int mx_halfspace_meets_box(const double *a, const double *b, const double *cc,
                           const double *box);
/* rank q's seeded layer width (mpi_ghosts.c): the same double on every rank */
double mx_layer_width(const run *R, int q);
/* the tile's grid of cells, R->gr; writes R->tile in cell order as S's first m points (R->sp,
 * room for m) and frees R->tile */
gtet_status mx_grid_build(run *R);
/* R->gr.far from the tile grid and the gathered boxes (mx_grid_build's caller, D11) */
gtet_status mx_grid_far(run *R);
/* append to out (mpt records) the tile points in conflict with Q not sent to rank `to`
 * before (for a hull facet, and a tet with a large answer, only those near the nearest one:
 * D3), and mark them sent */
gtet_status mx_answer(run *R, const query *Q, int to, vec *out);
/* the answer out[n0..) (ids: tile indices, not marked sent) filtered to the points near the
 * nearest one for a hull facet or a large tet answer, marked sent, records restored */
gtet_status mx_answer_near(run *R, int to, vec *out, size_t n0, int hull);

/* a ball's cell range in the tile grid (the whole grid for B->all): every tile point within
 * the ball lies in the cells lo..hi (mx_answer's scan range) */
void mx_ball_range(const grid *G, const ball *B, int lo[3], int hi[3]);

/* a round's answers to circumball queries from DT(X), X = the tile and the queries' vertices
 * (mpi_lift.c, proofs/distributed.md D12) */
typedef struct lift {
    int on;                     /* built: answer the ball queries with mx_answer_lift */
    size_t nx;                  /* X: S's first m points (the tile), then xp */
    mpt *xp;                    /* the queries' vertices that are not tile points */
    size_t *adj0;               /* nx + 1: X vertex i's neighbours in DT(X) are */
    uint32_t *adj;              /*   adj[adj0[i] .. adj0[i + 1] - 1] */
    uint64_t *mk;               /* vertex id -> X index: keys (NOID empty) ... */
    uint32_t *mv;               /* ... and values */
    size_t mcap;
    uint32_t *stamp, cur;       /* per X vertex: visited by the search numbered cur */
    uint32_t *queue;            /* the search's conflicting vertices */
    size_t qcap;
    uint64_t *work;             /* per asking rank: this round's exact tests for it; past
                                   LIFT_DUMP_LIMIT m the rest of the tile is sent (D12) */
    uint32_t (*tets)[4];        /* DT(X)'s tets, X indices ascending, open addressing (row
                                   [0] == UINT32_MAX empty): a query's tet found here has an
                                   empty answer */
    size_t tcap;
} lift;
/* decide from the queries qs[0..nq) whether the round's scans would visit more than a fixed
 * multiple of the tile's points; if so build L (L->on); else L->on = 0.  L (zeroed before the
 * first round) is kept from the previous round when it holds every vertex of qs's tets */
gtet_status mx_lift_build(run *R, const query *qs, size_t nq, lift *L);
gtet_status mx_answer_lift(run *R, lift *L, const query *Q, int to, vec *out);
void mx_lift_free(lift *L);

void mx_sort4(uint64_t *k);                   /* 4 ids ascending (mpi_ghosts.c) */
/* the hull facet opposite slot f of local tet tv, in ghost order (mpi_ghosts.c) */
void mx_hull_facet(const run *R, const uint32_t *tv, int f, uint32_t out[3]);
/* later rounds: DT(S) -> DT(S u N), N = S's points from n_old on (mpi_patch.c); *done = 0
 * when the caller must triangulate from scratch */
gtet_status mx_patch(run *R, size_t n_old, int *done);

/* tile point i sent to rank `to` before?  The bit of R->sent_any first: the answers ask this of
 * every point their filters pass (a sheet of the tile for a hull facet), and most tile points
 * were never sent anywhere, so the hash set is probed only for the few that were */
static inline int mx_sent(const run *R, size_t i, int to)
{
    if (!(R->sent_any[i >> 6] >> (i & 63) & 1)) return 0;
    return mx_hs_has(&R->sent, (uint64_t)i * (uint64_t)R->c.size + (uint64_t)to);
}

/* mark tile point i sent to rank `to`: 1 newly, 0 before, -1 out of memory */
static inline int mx_mark_sent(run *R, size_t i, int to)
{
    R->sent_any[i >> 6] |= (uint64_t)1 << (i & 63);
    int a = mx_hs_add(&R->sent, (uint64_t)i * (uint64_t)R->c.size + (uint64_t)to);
    R->nsent[to] += a > 0;
    return a;
}

/* the current local triangulation, patched or not (nothing: *nt = 0, NULL arrays) */
static inline void mx_local_mesh(const run *R, size_t *nt, const uint32_t **tv,
                                 const uint32_t **nb)
{
    if (R->ptv) {
        *nt = R->pnt;
        *tv = R->ptv;
        *nb = R->ptn;
    } else if (R->mesh) {
        *nt = gtet_mesh_num_tets(R->mesh);
        *tv = gtet_mesh_tets(R->mesh);
        *nb = gtet_mesh_neighbors(R->mesh);
    } else {
        *nt = 0;
        *tv = *nb = NULL;
    }
}

#endif
