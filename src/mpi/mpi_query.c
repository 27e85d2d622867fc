/* mpi_query.c -- the geometry of the conflict queries (conservative circumballs, boxes,
 * halfspaces: proofs/distributed.md D4) and their answering side: the tile's grid of cells and
 * the exact conflict tests of the tile points a query's ball or halfspace may reach.  Which
 * tile points can reach no other tile (D11) is mpi_far.c's. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

/* ------------------------------------------------------------------------------------------ */
/* geometry: conservative circumballs, boxes, halfspaces (proofs/distributed.md D4)           */
/* ------------------------------------------------------------------------------------------ */

/* The circumcentre's offset o from a (D4's formula) and D = (b-a).((c-a)x(d-a)), with every
 * operation in type T (double or long double: the same expression, D4's bound with T's unit
 * roundoff); L2 is the largest squared edge at a. */
#define TET_CENTRE(T, a, b, cc, d, o, D, L2)                                                   \
    do {                                                                                       \
        T ba_[3], ca_[3], da_[3];                                                              \
        for (int k_ = 0; k_ < 3; k_++) {                                                       \
            ba_[k_] = (T)(b)[k_] - (T)(a)[k_];                                                 \
            ca_[k_] = (T)(cc)[k_] - (T)(a)[k_];                                                \
            da_[k_] = (T)(d)[k_] - (T)(a)[k_];                                                 \
        }                                                                                      \
        T lb_ = ba_[0] * ba_[0] + ba_[1] * ba_[1] + ba_[2] * ba_[2];                           \
        T lc_ = ca_[0] * ca_[0] + ca_[1] * ca_[1] + ca_[2] * ca_[2];                           \
        T ld_ = da_[0] * da_[0] + da_[1] * da_[1] + da_[2] * da_[2];                           \
        (L2) = lb_ > lc_ ? lb_ : lc_;                                                          \
        (L2) = ld_ > (L2) ? ld_ : (L2);                                                        \
        T x1_[3] = {ca_[1] * da_[2] - ca_[2] * da_[1], ca_[2] * da_[0] - ca_[0] * da_[2],      \
                    ca_[0] * da_[1] - ca_[1] * da_[0]};                                        \
        T x2_[3] = {da_[1] * ba_[2] - da_[2] * ba_[1], da_[2] * ba_[0] - da_[0] * ba_[2],      \
                    da_[0] * ba_[1] - da_[1] * ba_[0]};                                        \
        T x3_[3] = {ba_[1] * ca_[2] - ba_[2] * ca_[1], ba_[2] * ca_[0] - ba_[0] * ca_[2],      \
                    ba_[0] * ca_[1] - ba_[1] * ca_[0]};                                        \
        (D) = ba_[0] * x1_[0] + ba_[1] * x1_[1] + ba_[2] * x1_[2];                             \
        for (int k_ = 0; k_ < 3; k_++)                                                         \
            (o)[k_] = (lb_ * x1_[k_] + lc_ * x2_[k_] + ld_ * x3_[k_]) / (2 * (D));             \
    } while (0)

void mx_tet_ball(const double *a, const double *b, const double *cc, const double *d,
                     ball *B)
{
    double o[3], D, L2;
    TET_CENTRE(double, a, b, cc, d, o, D, L2);
    double L = sqrt(L2);
    B->all = 1;
    if (!(L >= 1e-100 && L <= 1e100) || !(fabs(D) > 0)) return;
    double cond = L * L * L / fabs(D);
    if (!(cond <= 1e12)) return;
    double R = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    /* the centre's floating error is below 42 eps cond R (D4); 200 eps cond (R + L) covers it,
     * 1e-14 (amax + R) the rounding of a + o and |o|, and 1e-9 R that of R and of this sum: a
     * tight ball (the thin lens of a flat tet's huge ball holds many points near its sphere,
     * each an exact test in the answers) */
    double err = 200 * DBL_EPSILON * cond * (R + L), amax = 0;
    double c[3];
    if (err > 1e-10 * R && LDBL_EPSILON < DBL_EPSILON) {
        /* a flat tet (the hull's): its double centre's error bound is the ball's slack, up to
         * the whole tile's width for a sphere of a million spacings (NOTES.md E200); the same
         * formula in long double has the same bound with LDBL_EPSILON (D4), and the centre and
         * radius rounded to double are covered by the 1e-14 and 1e-9 terms as before */
        long double ol[3], Dl, L2l;
        TET_CENTRE(long double, a, b, cc, d, ol, Dl, L2l);
        long double Ll = sqrtl(L2l), condl = Ll * Ll * Ll / fabsl(Dl);
        if (!(Ll >= 1e-100L && Ll <= 1e100L) || !(fabsl(Dl) > 0) || !(condl <= 1e12L)) return;
        long double Rl = sqrtl(ol[0] * ol[0] + ol[1] * ol[1] + ol[2] * ol[2]);
        R = (double)Rl;
        err = (double)(200 * LDBL_EPSILON * condl * (Rl + Ll));
        for (int k = 0; k < 3; k++) {
            c[k] = (double)((long double)a[k] + ol[k]);
            amax = mx_max(amax, fabs(a[k]));
        }
    } else {
        for (int k = 0; k < 3; k++) {
            c[k] = a[k] + o[k];
            amax = mx_max(amax, fabs(a[k]));
        }
    }
    memcpy(B->c, c, sizeof c);
    B->r = R * (1 + 1e-9) + err + 1e-14 * (amax + R);
    if (!isfinite(B->r) || !isfinite(B->c[0]) || !isfinite(B->c[1]) || !isfinite(B->c[2]))
        return;
    B->all = 0;
}
#undef TET_CENTRE


/* exact: does the closed halfspace {orient3d(a,b,c,x) >= 0} meet the box?  (an affine
 * function is largest at a corner) */
int mx_halfspace_meets_box(const double *a, const double *b, const double *cc,
                               const double *box)
{
    for (int m = 0; m < 8; m++) {
        double x[3] = {box[(m & 1) ? 3 : 0], box[(m & 2) ? 4 : 1], box[(m & 4) ? 5 : 2]};
        if (gtet_orient3d(a, b, cc, x) >= 0) return 1;
    }
    return 0;
}

/* floating filter for the same question, conservative (D4): 1 unless the box is surely on
 * the negative side */
typedef struct hspace {
    double a[3], nrm[3], tol;
    int all;
} hspace;

static void hspace_init(hspace *H, const double *a, const double *b, const double *cc)
{
    double ba[3], ca[3];
    for (int k = 0; k < 3; k++) {
        ba[k] = b[k] - a[k];
        ca[k] = cc[k] - a[k];
        H->a[k] = a[k];
    }
    H->nrm[0] = ba[1] * ca[2] - ba[2] * ca[1];
    H->nrm[1] = ba[2] * ca[0] - ba[0] * ca[2];
    H->nrm[2] = ba[0] * ca[1] - ba[1] * ca[0];
    double lb = sqrt(ba[0] * ba[0] + ba[1] * ba[1] + ba[2] * ba[2]);
    double lc = sqrt(ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2]);
    H->tol = 1e-12 * lb * lc;
    H->all = !(lb >= 1e-100 && lb <= 1e100 && lc >= 1e-100 && lc <= 1e100);
}

/* 1 unless x is surely on the negative side of H's plane (D4's tolerance) */
static int hspace_may_reach(const hspace *H, const double *p)
{
    double x[3] = {p[0] - H->a[0], p[1] - H->a[1], p[2] - H->a[2]};
    double v = H->nrm[0] * x[0] + H->nrm[1] * x[1] + H->nrm[2] * x[2];
    double len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    return !isfinite(v) || v >= -H->tol * len * 4;
}

/* 1 unless the box (lo[3], hi[3]) is surely on the negative side of H's plane, from its
 * corner x where the computed normal's function is largest (one evaluation, one square root:
 * the answers test every block of the grid and every cell of the blocks that pass; the eight
 * corners' square roots were most of a hull query's answer, NOTES.md E203).  With K = |b-a|
 * |c-a| and Dmax the largest distance from a to a corner: the computed normal differs from the
 * exact one by a few eps K and the evaluation at x errs by a few eps K |x - a|, so the exact
 * orient3d function's maximum over the box, at some corner, exceeds the computed value by at
 * most ~10 eps K Dmax, far below the 4 tol Dmax = 4e-12 K Dmax the test asks for (D4) */
static int hspace_meets_box(const hspace *H, const double *lo, const double *hi)
{
    if (H->all) return 1;
    double v = 0, d2 = 0;
    for (int k = 0; k < 3; k++) {
        double x = H->nrm[k] >= 0 ? hi[k] : lo[k];
        v += H->nrm[k] * (x - H->a[k]);
        double e = mx_max(fabs(lo[k] - H->a[k]), fabs(hi[k] - H->a[k]));
        d2 += e * e;
    }
    /* a box within 1e-100 of a, or a non-finite value: kept (D4's range) */
    if (!(d2 >= 1e-200 && d2 <= 1e200)) return 1;
    return !(v < -4 * H->tol * sqrt(d2) * (1 + 1e-9));
}

/* ------------------------------------------------------------------------------------------ */
/* the tile's grid (answers queries)                                                          */
/* ------------------------------------------------------------------------------------------ */

static int cell_of(const grid *G, int k, double x)
{
    double t = (x - G->lo[k]) * G->inv[k];
    if (!(t >= 0)) return 0;
    if (t >= G->g[k]) return G->g[k] - 1;
    return (int)t;
}

/* x as a float no greater (dir < 0) or no less (dir > 0) than x */
static float float_out(double x, int dir)
{
    float f = (float)x;
    if (dir < 0 && (double)f > x) f = nextafterf(f, -INFINITY);
    if (dir > 0 && (double)f < x) f = nextafterf(f, INFINITY);
    return f;
}

/* G->cb: each cell's points' bounding box, outward to floats.  A big circumball of a flat
 * hull tet crosses the tile in a lens thinner than a cell, over many cells whose points lie
 * outside it: testing the points' box skips those cells before their records, which cost a
 * cache miss each (61 % of the answers' time at 4M points, NOTES E81).  The box holds the
 * cell's points, so a ball that misses it (mx_ball_meets_box, whose distance is no larger
 * than any point's: floating subtraction, squares, sum and sqrt are monotone) misses every one
 * of them by the per-point test too: the skip changes no answer. */
static gtet_status grid_pyramid(run *R);

static gtet_status cell_boxes(run *R, size_t cells)
{
    grid *G = &R->gr;
    G->cb = mx_malloc((6 * cells + 1) * sizeof *G->cb);
    if (!G->cb) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    for (size_t ci = 0; ci < cells; ci++) {
        /* the points' box in doubles, then rounded outward once: float_out is monotone, so
         * this is the box of the points' rounded coordinates */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t j = G->start[ci]; j < G->start[ci + 1]; j++)
            for (int k = 0; k < 3; k++) {
                double x = R->sp[j].x[k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
        float *b = G->cb + 6 * ci;
        for (int k = 0; k < 3; k++) {
            b[k] = lo[k] == INFINITY ? INFINITY : float_out(lo[k], -1);
            b[3 + k] = hi[k] == -INFINITY ? -INFINITY : float_out(hi[k], 1);
        }
    }
    /* the blocks' boxes: each the union of its cells' (an empty block keeps lo = +inf, hi =
     * -inf and is skipped); 24 B a block stays in cache where the cells' boxes do not, and a
     * block's points' box, unlike its cells' nominal extent, stops short of the tile's faces */
    size_t nb = (size_t)G->b[0] * (size_t)G->b[1] * (size_t)G->b[2];
    G->bb = mx_malloc((6 * nb + 1) * sizeof *G->bb);
    if (!G->bb) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    for (size_t bi = 0; bi < nb; bi++)
        for (int k = 0; k < 3; k++) {
            G->bb[6 * bi + (size_t)k] = INFINITY;
            G->bb[6 * bi + 3 + (size_t)k] = -INFINITY;
        }
    size_t ci = 0;
    for (int z = 0; z < G->g[2]; z++)
        for (int y = 0; y < G->g[1]; y++)
            for (int x = 0; x < G->g[0]; x++, ci++) {
                float *b = G->bb + 6 * (((size_t)(z / GB) * (size_t)G->b[1] + (size_t)(y / GB)) *
                                            (size_t)G->b[0] + (size_t)(x / GB));
                const float *c = G->cb + 6 * ci;
                for (int k = 0; k < 3; k++) {
                    b[k] = c[k] < b[k] ? c[k] : b[k];
                    b[3 + k] = c[3 + k] > b[3 + k] ? c[3 + k] : b[3 + k];
                }
            }
    return grid_pyramid(R);
}

/* G->pyr: the block boxes (level 0), then level by level the unions of 2^3 nodes, to a single
 * node (scan_pyramid); an empty node keeps lo = +inf, hi = -inf */
static gtet_status grid_pyramid(run *R)
{
    grid *G = &R->gr;
    size_t tot = 0;
    int d[3] = {G->b[0], G->b[1], G->b[2]}, l = 0;
    for (;; l++) {
        G->poff[l] = tot;
        memcpy(G->pdim[l], d, sizeof d);
        tot += 6 * (size_t)d[0] * (size_t)d[1] * (size_t)d[2];
        if (d[0] == 1 && d[1] == 1 && d[2] == 1) break;
        for (int k = 0; k < 3; k++) d[k] = (d[k] + 1) / 2;
    }
    G->nlev = l + 1;
    G->pyr = mx_malloc((tot + 1) * sizeof *G->pyr);
    if (!G->pyr) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    memcpy(G->pyr, G->bb, 6 * (size_t)G->b[0] * (size_t)G->b[1] * (size_t)G->b[2] * sizeof *G->pyr);
    for (l = 1; l < G->nlev; l++) {
        const int *e = G->pdim[l], *c = G->pdim[l - 1];
        float *up = G->pyr + G->poff[l];
        const float *dn = G->pyr + G->poff[l - 1];
        for (size_t i = 0; i < 6 * (size_t)e[0] * (size_t)e[1] * (size_t)e[2]; i += 6)
            for (int k = 0; k < 3; k++) {
                up[i + (size_t)k] = INFINITY;
                up[i + 3 + (size_t)k] = -INFINITY;
            }
        for (int z = 0; z < c[2]; z++)
            for (int y = 0; y < c[1]; y++)
                for (int x = 0; x < c[0]; x++) {
                    const float *b = dn + 6 * (((size_t)z * (size_t)c[1] + (size_t)y) *
                                                   (size_t)c[0] + (size_t)x);
                    float *u = up + 6 * (((size_t)(z / 2) * (size_t)e[1] + (size_t)(y / 2)) *
                                             (size_t)e[0] + (size_t)(x / 2));
                    for (int k = 0; k < 3; k++) {
                        u[k] = b[k] < u[k] ? b[k] : u[k];
                        u[3 + k] = b[3 + k] > u[3 + k] ? b[3 + k] : u[3 + k];
                    }
                }
    }
    return GTET_OK;
}

/* the tile grid's cell of a tile point */
static size_t tile_cell(const grid *G, const double *x)
{
    return ((size_t)cell_of(G, 2, x[2]) * (size_t)G->g[1] + (size_t)cell_of(G, 1, x[1])) *
               (size_t)G->g[0] + (size_t)cell_of(G, 0, x[0]);
}

/* mx_grid_build's first pass: at most this many runs of consecutive cells */
#define CELL_RUNS 1024
gtet_status mx_grid_build(run *R)
{
    grid *G = &R->gr;
    size_t m = R->m;
    if (m == 0) return GTET_OK;
    if (R->scap < m) return mx_fail(&R->c, GTET_ERR_INTERNAL, "rank %d: no room for the tile in S",
                                    R->c.rank);
    const double *box = R->box + 6 * R->c.rank;
    double e[3], vol = 1, emax = 0;
    for (int k = 0; k < 3; k++) {
        G->lo[k] = box[k];
        G->hi[k] = box[3 + k];
        e[k] = box[3 + k] - box[k];
        emax = fmax(emax, e[k]);
    }
    for (int k = 0; k < 3; k++) vol *= fmax(e[k], emax * 1e-3);
    double target = fmax(1.0, (double)m / 2);
    double h = cbrt(vol / target);
    size_t cells = 1;
    for (int k = 0; k < 3; k++) {
        double gk = (e[k] > 0 && h > 0 && isfinite(h)) ? floor(e[k] / h) : 1;
        if (!(gk >= 1)) gk = 1;
        if (gk > 1024) gk = 1024;
        G->g[k] = (int)gk;
        G->inv[k] = e[k] > 0 ? G->g[k] / e[k] : 0;
        if (!isfinite(G->inv[k])) G->inv[k] = 0;
        G->b[k] = (G->g[k] + GB - 1) / GB;
        cells *= (size_t)G->g[k];
    }
    G->start = mx_calloc(cells + 1, sizeof *G->start);
    uint32_t *cid = mx_malloc(m * sizeof *cid);
    if (!G->start || !cid || m > UINT32_MAX) {
        free(cid);
        return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    }
    /* the tile itself in cell order, written as S's first m points: cell ci holds S's points
     * start[ci] .. start[ci + 1] - 1, which answers scan in memory order (32 B records at random
     * through an index were the answers' largest cost before); S holds the tile from here on,
     * so R->tile goes (one copy of the tile in memory, not two).  Two stable passes (NOTES.md
     * E222): by runs of 2^sh consecutive cells, at most CELL_RUNS of them, whose counts and write
     * positions the caches hold (one pass straight to the cells counted and wrote each record at
     * random, a miss each: E208); then each run's records, copied into the tile's block,
     * counted and written to their cells, all within the run's span of S and of start[].  A
     * cell's points keep the tile's order either way. */
    int sh = 0;
    while ((cells - 1) >> sh >= CELL_RUNS) sh++;
    size_t runs = ((cells - 1) >> sh) + 1;
    size_t *rp = mx_calloc(runs + 1, sizeof *rp);
    if (!rp) {
        free(cid);
        return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
    }
    for (size_t i = 0; i < m; i++) {
        size_t ci = tile_cell(G, R->tile[i].x);
        cid[i] = (uint32_t)ci;
        rp[(ci >> sh) + 1]++;
    }
    for (size_t b = 0; b < runs; b++) rp[b + 1] += rp[b];
    for (size_t i = 0; i < m; i++) R->sp[rp[cid[i] >> sh]++] = R->tile[i];
    free(cid);
    /* rp[b] is run b's end now; start[] counted, summed and advanced run by run: start[c0],
     * the run's first, is final when its run begins */
    for (size_t b = 0, lo = 0; b < runs; b++) {
        size_t hi = rp[b], len = hi - lo, c0 = b << sh, c1 = c0 + ((size_t)1 << sh);
        if (c1 > cells) c1 = cells;
        memcpy(R->tile, R->sp + lo, len * sizeof *R->tile);
        for (size_t i = 0; i < len; i++) G->start[tile_cell(G, R->tile[i].x) + 1]++;
        for (size_t c = c0; c < c1; c++) G->start[c + 1] += G->start[c];
        for (size_t i = 0; i < len; i++) R->sp[G->start[tile_cell(G, R->tile[i].x)]++] = R->tile[i];
        lo = hi;
    }
    free(rp);
    free(R->tile);
    R->tile = NULL;
    for (size_t ci = cells; ci > 0; ci--) G->start[ci] = G->start[ci - 1];
    G->start[0] = 0;
    return cell_boxes(R, cells);
}

/* A ball's reach inside a box (lo[3], hi[3]) that holds the points of interest, axis by axis:
 * a point x of the box within r of c has (x_k - c_k)^2 <= r^2 - d_j^2 - d_l^2 for the two other
 * axes j, l, d_j the distance from c_j to the box's range on axis j.  The huge ball of a flat
 * tet near the global hull meets the box in a thin lens, and its range c +- r was the whole
 * grid: every block visited (NOTES E132).  Computed with r (1 + 1e-9), whose excess
 * (~2e-9 r^2) exceeds the rounding of the squares and differences (< 10 eps r^2), and widened
 * like the ball's own range: every such x has |x_k - c_k| <= h[k], so the cells from
 * c_k - h[k] to c_k + h[k] hold it (the cell formula is monotone). */
void mx_ball_reach(const double *lo, const double *hi, const ball *B, double h[3])
{
    double r = B->r * (1 + 1e-9), d2[3];
    for (int k = 0; k < 3; k++) {
        double d = mx_max(lo[k] - B->c[k], mx_max(0.0, B->c[k] - hi[k]));
        d2[k] = d * d;
    }
    for (int k = 0; k < 3; k++) {
        h[k] = sqrt(mx_max(r * r - d2[(k + 1) % 3] - d2[(k + 2) % 3], 0.0));
        h[k] += 1e-9 * (fabs(B->c[k]) + h[k]);
    }
}

/* A ball's cell range narrowed to the tile (the tile's box G->lo..hi is its points' exact
 * bounding box): mx_ball_reach. */
static void ball_clip(const grid *G, const ball *B, int lo[3], int hi[3])
{
    double h[3];
    mx_ball_reach(G->lo, G->hi, B, h);
    for (int k = 0; k < 3; k++) {
        int a = cell_of(G, k, B->c[k] - h[k]), b = cell_of(G, k, B->c[k] + h[k]);
        if (a > lo[k]) lo[k] = a;   /* both ranges hold cell_of(c_k): they meet */
        if (b < hi[k]) hi[k] = b;
    }
}

void mx_ball_range(const grid *G, const ball *B, int lo[3], int hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = 0;
        hi[k] = G->g[k] - 1;
    }
    if (B->all) return;
    for (int k = 0; k < 3; k++) {
        double r = B->r * (1 + 1e-9);
        lo[k] = cell_of(G, k, B->c[k] - r);
        hi[k] = cell_of(G, k, B->c[k] + r);
    }
    ball_clip(G, B, lo, hi);
}

/* The tets' answers are filtered like the hull facets' (below) only when they hold more than
 * this many points: a few flat tets of a rank's local hull have spheres that hold a thin lens of
 * another tile along a face of the global box (thousands of points, nearly all irrelevant to
 * the asker's star: NOTES.md Q46, E216); a uniform set's other answers hold a few points each */
#ifndef NEAR_TET_MIN
#define NEAR_TET_MIN 64
#endif

/* A query's answer (out's records from n0 on, ids still tile indices, not yet marked sent):
 * for a hull facet, and for a tet whose answer holds more than NEAR_TET_MIN points, only the
 * points within the layer width of this tile of the nearest one's distance to rank `to`'s box;
 * those kept are marked sent and get their records back.  The halfspace beyond a facet of
 * `to`'s local hull holds a whole sheet of this tile along a face of the global box; a non-empty
 * answer whenever a conflicting point was not sent is all D3 and D8 need (any point of it
 * destroys the simplex in `to`'s next triangulation, whose new simplices are queried again).
 * GTET_MPI_NEAR=off: the tets' answers whole; =on: every tet's answer cut (the tests compare
 * these with the default). */
gtet_status mx_answer_near(run *R, int to, vec *out, size_t n0, int hull)
{
    mpt *o = (mpt *)out->p;
    const double *box = R->box + 6 * to;
    int filter = hull;
    if (!hull && out->n > n0) {
        int mode = mx_env_mode("GTET_MPI_NEAR");
        filter = mode > 0 || (mode == 0 && out->n - n0 > NEAR_TET_MIN);
    }
    double lim = INFINITY;
    if (filter) {
        double dmin = INFINITY;
        for (size_t i = n0; i < out->n; i++) dmin = fmin(dmin, mx_box_dist(box, o[i].x));
        lim = dmin + mx_layer_width(R, R->c.rank);
        R->c.st->answers_near += !hull;
    }
    size_t w = n0;
    for (size_t i = n0; i < out->n; i++) {
        if (filter && !(mx_box_dist(box, o[i].x) <= lim)) continue;
        uint64_t idx = o[i].id;
        if (mx_mark_sent(R, idx, to) < 0)
            return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        o[w] = R->sp[idx];
        w++;
    }
    out->n = w;
    return GTET_OK;
}

/* One query's scan: its ball or halfspace, the cell range, where the answer goes */
typedef struct scan {
    const query *Q;
    ball B;
    hspace H;
    int hull, to;
    int lo[3], hi[3];
    vec *out;
} scan;

/* one point of the scan: the floating filter, "sent before", the exact predicate; a conflict
 * is appended with its tile index as id, not yet marked sent (mx_answer_near) */
static gtet_status scan_point(run *R, const scan *W, uint32_t j)
{
    const query *Q = W->Q;
    const mpt *p = &R->sp[j];
    if (p->id == Q->id[0] || p->id == Q->id[1] || p->id == Q->id[2] || p->id == Q->id[3])
        return GTET_OK;
    int conflict;
    /* a point sent to `to` before is not answered whether or not it conflicts: asked after
     * the floating filter, before the exact predicate */
    if (W->hull) {
        /* the block filter's test, point by point (D4) */
        if (!W->H.all && !hspace_may_reach(&W->H, p->x)) return GTET_OK;
        if (mx_sent(R, j, W->to)) return GTET_OK;
        R->c.st->answer_tests++;
        conflict = gtet_ghost_conflict(Q->p[0], Q->p[1], Q->p[2], p->x) > 0;
    } else {
        if (!W->B.all) {
            double d0 = p->x[0] - W->B.c[0], d1 = p->x[1] - W->B.c[1], d2 = p->x[2] - W->B.c[2];
            if (sqrt(d0 * d0 + d1 * d1 + d2 * d2) > W->B.r * (1 + 1e-9)) return GTET_OK;
        }
        if (mx_sent(R, j, W->to)) return GTET_OK;
        R->c.st->answer_tests++;
        conflict = gtet_insphere_sos(Q->p[0], Q->p[1], Q->p[2], Q->p[3], p->x) > 0;
    }
    if (!conflict) return GTET_OK;
    mpt *o = mx_vec_push(W->out);
    if (!o) return mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    *o = *p;
    o->id = j;   /* the tile index until mx_answer_near (a scan visits a point once) */
    return GTET_OK;
}

/* does the scan's ball or halfspace meet the float box b (lo[3], hi[3])?  (D4: a box that
 * holds points and is missed holds no point the per-point filters would pass) */
static int scan_meets(const scan *W, const float *b)
{
    if (!W->hull && W->B.all) return 1;
    double bb[6];
    for (int k = 0; k < 6; k++) bb[k] = b[k];
    return W->hull ? hspace_meets_box(&W->H, bb, bb + 3) : mx_ball_meets_box(&W->B, bb);
}

/* the cells of block (bx, by, bz) in the scan's range, skipped when their points' box is
 * missed (cell_boxes) */
static gtet_status scan_block(run *R, const scan *W, int bx, int by, int bz)
{
    const grid *G = &R->gr;
    int c0[3] = {bx * GB, by * GB, bz * GB};
    for (int z = c0[2]; z < c0[2] + GB && z <= W->hi[2]; z++) {
        if (z < W->lo[2]) continue;
        for (int y = c0[1]; y < c0[1] + GB && y <= W->hi[1]; y++) {
            if (y < W->lo[1]) continue;
            for (int x = c0[0]; x < c0[0] + GB && x <= W->hi[0]; x++) {
                if (x < W->lo[0]) continue;
                size_t ci = ((size_t)z * (size_t)G->g[1] + (size_t)y) * (size_t)G->g[0] + (size_t)x;
                if (G->start[ci] == G->start[ci + 1] || !scan_meets(W, G->cb + 6 * ci)) continue;
                for (uint32_t j = G->start[ci]; j < G->start[ci + 1]; j++) {
                    gtet_status s = scan_point(R, W, j);
                    if (s != GTET_OK) return s;
                }
            }
        }
    }
    return GTET_OK;
}

/* A halfspace's blocks through the pyramid of block boxes (grid_pyramid): a node whose box the
 * halfspace misses holds no point the filters pass (the box holds its blocks' points), so
 * only the blocks along the facet's plane and beyond it are visited -- on a sphere, where
 * every tile point is on the hull, the sheet beyond a facet is a few blocks, not the grid */
static gtet_status scan_pyramid(run *R, const scan *W)
{
    const grid *G = &R->gr;
    int stack[3 * 8 * 24 + 8][4], ns = 0;
    stack[ns][0] = G->nlev - 1;
    stack[ns][1] = stack[ns][2] = stack[ns][3] = 0;
    ns++;
    while (ns > 0) {
        ns--;
        int l = stack[ns][0], x = stack[ns][1], y = stack[ns][2], z = stack[ns][3];
        const int *d = G->pdim[l];
        const float *b = G->pyr + G->poff[l] +
                         6 * (((size_t)z * (size_t)d[1] + (size_t)y) * (size_t)d[0] + (size_t)x);
        if (!(b[0] <= b[3]) || !scan_meets(W, b)) continue;
        if (l == 0) {
            gtet_status s = scan_block(R, W, x, y, z);
            if (s != GTET_OK) return s;
            continue;
        }
        const int *e = G->pdim[l - 1];
        for (int k = 7; k >= 0; k--) {
            int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1 & 1), cz = 2 * z + (k >> 2 & 1);
            if (cx >= e[0] || cy >= e[1] || cz >= e[2]) continue;
            stack[ns][0] = l - 1;
            stack[ns][1] = cx;
            stack[ns][2] = cy;
            stack[ns][3] = cz;
            ns++;
        }
    }
    return GTET_OK;
}

/* Answer: append to out (mpt records) the tile points in conflict with q that were not sent
 * to rank `to` before; mark them sent. */
gtet_status mx_answer(run *R, const query *Q, int to, vec *out)
{
    grid *G = &R->gr;
    /* every tile point was sent to `to` before: nothing to answer (6c) */
    if (R->m == 0 || R->nsent[to] == R->m) return GTET_OK;
    scan W;
    W.Q = Q;
    W.hull = Q->id[3] == NOID;
    W.to = to;
    W.out = out;
    size_t n0 = out->n;
    if (W.hull) {
        hspace_init(&W.H, Q->p[0], Q->p[1], Q->p[2]);
        for (int k = 0; k < 3; k++) {
            W.lo[k] = 0;
            W.hi[k] = G->g[k] - 1;
        }
        gtet_status s = scan_pyramid(R, &W);
        return s != GTET_OK ? s : mx_answer_near(R, to, out, n0, 1);
    }
    mx_tet_ball(Q->p[0], Q->p[1], Q->p[2], Q->p[3], &W.B);
    mx_ball_range(G, &W.B, W.lo, W.hi);
    /* blocks of GB^3 cells first: skipped when empty or when the ball misses their points'
     * box (a flat tet near the hull has a huge ball whose cell range is the whole tile) */
    for (int bz = W.lo[2] / GB; bz <= W.hi[2] / GB; bz++)
        for (int by = W.lo[1] / GB; by <= W.hi[1] / GB; by++)
            for (int bx = W.lo[0] / GB; bx <= W.hi[0] / GB; bx++) {
                const float *fb = G->bb + 6 * (((size_t)bz * (size_t)G->b[1] + (size_t)by) *
                                                   (size_t)G->b[0] + (size_t)bx);
                if (!(fb[0] <= fb[3]) || !scan_meets(&W, fb)) continue;
                gtet_status s = scan_block(R, &W, bx, by, bz);
                if (s != GTET_OK) return s;
            }
    return mx_answer_near(R, to, out, n0, 0);
}
