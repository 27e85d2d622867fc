/* mpi_far.c -- the tile points no star tet of which can reach another tile
 * (proofs/distributed.md D11), certified per cell of the tile's grid (mpi_query.c builds the
 * grid) against the gathered boxes of the other tiles: mx_grid_far. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

/* ------------------------------------------------------------------------------------------ */
/* tile points no star tet of which can reach another tile (proofs/distributed.md D11)        */
/* ------------------------------------------------------------------------------------------ */

/* one axis of the grid for D11: a[i] <= every point of cell i <= b[i] (checked per cell by
 * far_cells), step >= a[i+1] - a[i] >= dmin, span >= b[i+1] - a[i], all exact bounds of the
 * computed doubles (a floating difference of two doubles is within a relative 2^-53 of the
 * exact one; the factors 1 -+ 1e-9 cover it and their own rounding) */
typedef struct far_axis {
    double *a, *b, step, span, dmin;
    int klo, khi;   /* the blocks a ball of radius rho through a point of cell i must hold
                       start in [i - klo + 1, i + khi] (D11) */
} far_axis;

/* 0 when the axis cannot certify anything (one cell, a flat axis, overflow) */
static int far_axis_init(const grid *G, int k, far_axis *X)
{
    int g = G->g[k];
    double cw = G->inv[k] > 0 ? 1 / G->inv[k] : 0;
    double eta = 1e-9 * (fabs(G->lo[k]) + fabs(G->hi[k]));
    if (g < 3 || !(cw > 0) || !isfinite(cw) || !isfinite(eta)) return 0;
    X->step = X->span = 0;
    X->dmin = INFINITY;
    for (int i = 0; i < g; i++) {
        X->a[i] = (G->lo[k] + i * cw) - eta;
        X->b[i] = (G->lo[k] + (i + 1) * cw) + eta;
    }
    for (int i = 0; i + 1 < g; i++) {
        X->step = mx_max(X->step, X->a[i + 1] - X->a[i]);
        X->span = mx_max(X->span, X->b[i + 1] - X->a[i]);
        X->dmin = fmin(X->dmin, X->a[i + 1] - X->a[i]);
    }
    X->step *= 1 + 1e-9;
    X->span *= 1 + 1e-9;
    X->dmin *= 1 - 1e-9;
    return X->dmin > 0 && isfinite(X->step + X->span);
}

/* occ[c]: cell c holds a point and its points' box lies in [a, b] on every axis */
static void far_occupied(const grid *G, far_axis X[3], unsigned char *occ)
{
    size_t ci = 0;
    for (int z = 0; z < G->g[2]; z++)
        for (int y = 0; y < G->g[1]; y++)
            for (int x = 0; x < G->g[0]; x++, ci++) {
                const float *cb = G->cb + 6 * ci;
                int i[3] = {x, y, z};
                int in = G->start[ci] < G->start[ci + 1];
                for (int k = 0; k < 3 && in; k++)
                    in = (double)cb[k] >= X[k].a[i[k]] && (double)cb[3 + k] <= X[k].b[i[k]];
                occ[ci] = (unsigned char)in;
            }
}

/* the summed-area table's entry for blocks before (i, j, l) (index 0: the zero border) */
#define SAT(i, j, l) sat[((size_t)(l) * s1 + (size_t)(j)) * s0 + (size_t)(i)]

/* sat: summed-area table ((g0 - 1) x (g1 - 1) x (g2 - 1) blocks, one more in each direction)
 * of "the 2 x 2 x 2 cells from this one on hold no occupied cell" */
static void far_empty_blocks(const grid *G, const unsigned char *occ, uint32_t *sat)
{
    size_t s0 = (size_t)G->g[0], s1 = (size_t)G->g[1];   /* the table is g0 x g1 x g2 */
    for (int z = 0; z + 1 < G->g[2]; z++)
        for (int y = 0; y + 1 < G->g[1]; y++)
            for (int x = 0; x + 1 < G->g[0]; x++) {
                int any = 0;
                for (int d = 0; d < 8 && !any; d++)
                    any = occ[((size_t)(z + (d >> 2)) * s1 + (size_t)(y + ((d >> 1) & 1))) * s0 +
                              (size_t)(x + (d & 1))];
                size_t X1 = (size_t)x + 1, Y1 = (size_t)y + 1, Z1 = (size_t)z + 1;
                SAT(X1, Y1, Z1) = (uint32_t)!any + SAT(X1 - 1, Y1, Z1) + SAT(X1, Y1 - 1, Z1) +
                                  SAT(X1, Y1, Z1 - 1) - SAT(X1 - 1, Y1 - 1, Z1) -
                                  SAT(X1 - 1, Y1, Z1 - 1) - SAT(X1, Y1 - 1, Z1 - 1) +
                                  SAT(X1 - 1, Y1 - 1, Z1 - 1);
            }
}

/* D11 for cell i (ranges checked by the caller): no empty block starts in
 * [i - klo + 1, i + khi] */
static int far_cell_covered(const grid *G, const far_axis X[3], const uint32_t *sat,
                            const int i[3])
{
    size_t s0 = (size_t)G->g[0], s1 = (size_t)G->g[1];
    size_t lo[3], hi[3];   /* table indices: blocks lo+1 .. hi+1 minus the border */
    for (int k = 0; k < 3; k++) {
        lo[k] = (size_t)(i[k] - X[k].klo + 1);
        hi[k] = (size_t)(i[k] + X[k].khi) + 1;
    }
    uint32_t n = SAT(hi[0], hi[1], hi[2]) - SAT(lo[0], hi[1], hi[2]) - SAT(hi[0], lo[1], hi[2]) -
                 SAT(hi[0], hi[1], lo[2]) + SAT(lo[0], lo[1], hi[2]) + SAT(lo[0], hi[1], lo[2]) +
                 SAT(hi[0], lo[1], lo[2]) - SAT(lo[0], lo[1], lo[2]);
    return n == 0;
}
#undef SAT

/* the floating distance between the box [a, b] (per axis) and box (lo[3], hi[3]); the exact
 * distance is at least this times 1 - 6 * 2^-53 (each step a correctly rounded operation on
 * non-negative values) */
static double far_box_gap(const double *a, const double *b, const double *box)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double e = mx_max(0.0, mx_max(box[k] - b[k], a[k] - box[3 + k]));
        d2 += e * e;
    }
    return sqrt(d2);
}

/* cell ci (its indices i) certified by D11 and at least 2 rho from every other tile's box */
static int far_cell(const run *R, const far_axis X[3], const uint32_t *sat, const int i[3],
                    double rho)
{
    const grid *G = &R->gr;
    for (int k = 0; k < 3; k++)
        if (i[k] < X[k].klo || i[k] + X[k].khi > G->g[k] - 2) return 0;
    if (!far_cell_covered(G, X, sat, i)) return 0;
    double a[3], b[3];
    for (int k = 0; k < 3; k++) {
        a[k] = X[k].a[i[k]];
        b[k] = X[k].b[i[k]];
    }
    for (int q = 0; q < R->c.size; q++) {
        if (q == R->c.rank || R->tcount[q] == 0) continue;
        if (!(far_box_gap(a, b, R->box + 6 * q) * (1 - 1e-9) > 2 * rho)) return 0;
    }
    return 1;
}

/* GTET_MPI_FAR=off in the environment: no tile point is far, every star tet takes the ball
 * test.  The queries sent must be the same either way (a far vertex's tets have balls that miss
 * every other tile's box); tests/mpi/run_tests.sh compares the two. */
static int far_off(void)
{
    const char *e = getenv("GTET_MPI_FAR");
    return e && (strcmp(e, "off") == 0 || strcmp(e, "0") == 0);
}

gtet_status mx_grid_far(run *R)
{
    grid *G = &R->gr;
    if (R->m == 0) return GTET_OK;
    G->far = mx_calloc(R->m / 64 + 1, sizeof *G->far);
    size_t cells = (size_t)G->g[0] * (size_t)G->g[1] * (size_t)G->g[2];
    double *ab = mx_malloc(2 * (size_t)(G->g[0] + G->g[1] + G->g[2]) * sizeof *ab);
    unsigned char *occ = mx_malloc(cells);
    uint32_t *sat = mx_calloc(cells, sizeof *sat);
    gtet_status s = GTET_OK;
    if (!G->far || !ab || !occ || !sat) {
        s = mx_fail(&R->c, GTET_ERR_OUT_OF_MEMORY, "out of memory (tile grid)");
        goto done;
    }
    if (far_off()) goto done;
    far_axis X[3];
    double s2 = 0;   /* twice the cube's half-side: above every axis's step + span */
    for (int k = 0, at = 0; k < 3; at += 2 * G->g[k], k++) {
        X[k].a = ab + at;
        X[k].b = ab + at + G->g[k];
        if (!far_axis_init(G, k, &X[k])) goto done;
        s2 = mx_max(s2, X[k].step + X[k].span);
    }
    double hs = s2 * 0.5 * (1 + 1e-9);             /* 2 hs > step + span on every axis */
    double rho = hs * 1.7320509 * (1 + 1e-9);      /* >= sqrt(3) hs */
    for (int k = 0; k < 3; k++) {
        /* klo dmin >= rho + hs and khi dmin > span + rho - hs */
        double klo = floor((rho + hs) / X[k].dmin * (1 + 1e-9)) + 1;
        double khi = floor((X[k].span + rho - hs) / X[k].dmin * (1 + 1e-9)) + 1;
        if (!(klo <= 64 && khi <= 64)) goto done;   /* a thin axis: nothing certified */
        X[k].klo = (int)klo;
        X[k].khi = (int)khi;
    }
    far_occupied(G, X, occ);
    far_empty_blocks(G, occ, sat);
    size_t ci = 0;
    for (int z = 0; z < G->g[2]; z++)
        for (int y = 0; y < G->g[1]; y++)
            for (int x = 0; x < G->g[0]; x++, ci++) {
                int i[3] = {x, y, z};
                if (!occ[ci] || !far_cell(R, X, sat, i, rho)) continue;
                for (uint32_t j = G->start[ci]; j < G->start[ci + 1]; j++)
                    G->far[j >> 6] |= (uint64_t)1 << (j & 63);
            }
done:
    free(ab);
    free(occ);
    free(sat);
    return s;
}
