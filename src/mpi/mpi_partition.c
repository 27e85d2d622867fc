/* mpi_partition.c -- step 4 of gtet_triangulate_mpi: a kd tree of boxes built by every rank
 * from one gathered sample, one leaf (tile) per rank; the points go to their tile, and the
 * tiles' bounding boxes and counts are gathered. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

static int g_axis;
static int cmp_axis(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 3; k++) {
        int ax = (g_axis + k) % 3;
        if (x[ax] < y[ax]) return -1;
        if (x[ax] > y[ax]) return 1;
    }
    return 0;
}

static int kd_build(run *R, double *smp, size_t ns, int lo, int hi)
{
    int id = R->nkd++;
    struct kdn *nd = &R->kd[id];
    if (hi - lo == 1) {
        nd->leaf = lo;
        nd->left = nd->right = -1;
        return id;
    }
    nd->leaf = -1;
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < ns; i++)
        for (int k = 0; k < 3; k++) {
            mn[k] = fmin(mn[k], smp[3 * i + k]);
            mx[k] = fmax(mx[k], smp[3 * i + k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (ns && mx[k] - mn[k] > mx[axis] - mn[axis]) axis = k;
    int kl = (hi - lo) / 2;
    g_axis = axis;
    mpi_sort(smp, ns, 3 * sizeof(double), cmp_axis);
    size_t at = (size_t)((double)ns * kl / (hi - lo));
    double split = ns ? smp[3 * (at < ns ? at : ns - 1) + axis] : 0.0;
    size_t j = 0;
    while (j < ns && smp[3 * j + axis] < split) j++;
    nd->axis = axis;
    nd->split = split;
    int l = kd_build(R, smp, j, lo, lo + kl);
    int r = kd_build(R, smp + 3 * j, ns - j, lo + kl, hi);
    R->kd[id].left = l;   /* nd may have moved? no: kd is preallocated */
    R->kd[id].right = r;
    return id;
}

static int kd_rank(const run *R, const double *x)
{
    int id = 0;
    while (R->kd[id].leaf < 0)
        id = x[R->kd[id].axis] < R->kd[id].split ? R->kd[id].left : R->kd[id].right;
    return R->kd[id].leaf;
}

gtet_status mx_step_partition(run *R)
{
    mctx *c = &R->c;
    int P = c->size;
    gtet_status s = GTET_OK;
    size_t S = 2048 * (size_t)P;
    if (S > ((size_t)1 << 20)) S = (size_t)1 << 20;
    size_t mine = R->nf;
    if (R->V > S) mine = (size_t)(((uint64_t)R->nf * S + R->V - 1) / R->V);
    if (mine > R->nf) mine = R->nf;
    int *cnt = mx_malloc(2 * (size_t)P * sizeof *cnt);
    double *my = mx_malloc((3 * mine + 1) * sizeof *my);
    R->kd = mx_malloc(2 * (size_t)P * sizeof *R->kd);
    R->box = mx_malloc(6 * (size_t)P * sizeof *R->box);
    R->tcount = mx_malloc((size_t)P * sizeof *R->tcount);
    double *smp = NULL;
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    int *dst = mx_malloc(R->nf * sizeof *dst);
    mpt *sb = mx_malloc(R->nf * sizeof *sb);
    if (!cnt || !my || !R->kd || !R->box || !R->tcount || !scnt || !rcnt || !pos || !dst || !sb)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < mine; k++) {
        size_t i = (size_t)((double)k * (double)R->nf / (double)mine);
        memcpy(my + 3 * k, R->fp[i].x, 3 * sizeof(double));
    }
    int mi = (int)(3 * mine);
    MPI_Allgather(&mi, 1, MPI_INT, cnt, 1, MPI_INT, c->comm);
    size_t tot = 0;
    for (int q = 0; q < P; q++) {
        cnt[P + q] = (int)tot;
        tot += (size_t)cnt[q];
    }
    smp = mx_malloc((tot + 1) * sizeof *smp);
    if (!smp) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    MPI_Allgatherv(my, mi, MPI_DOUBLE, smp, cnt, cnt + P, MPI_DOUBLE, c->comm);
    R->nkd = 0;
    kd_build(R, smp, tot / 3, 0, P);
    for (size_t i = 0; i < R->nf; i++) {
        dst[i] = kd_rank(R, R->fp[i].x);
        scnt[dst[i]]++;
    }
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t i = 0; i < R->nf; i++) sb[pos[dst[i]]++] = R->fp[i];
    /* the first occurrences are in sb now and no later step reads them: their block can take
     * the tile the exchange receives instead of fresh memory (NOTES.md Q14, E121) */
    free(R->fp);
    R->fp = NULL;
    {
        void *r;
        if ((s = mx_exchange(c, sb, scnt, sizeof(mpt), &r, rcnt, &R->m, 0)) != GTET_OK)
            goto done;
        R->tile = r;
    }
    for (int k = 0; k < 4; k++) R->seed_rank[k] = kd_rank(R, R->seed[k].x);
    double bb[7] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY, 0};
    for (size_t i = 0; i < R->m; i++)
        for (int k = 0; k < 3; k++) {
            bb[k] = fmin(bb[k], R->tile[i].x[k]);
            bb[3 + k] = fmax(bb[3 + k], R->tile[i].x[k]);
        }
    bb[6] = (double)R->m;
    double *all = mx_malloc(7 * (size_t)P * sizeof *all);
    if (!all) s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    MPI_Allgather(bb, 7, MPI_DOUBLE, all, 7, MPI_DOUBLE, c->comm);
    for (int q = 0; q < P; q++) {
        memcpy(R->box + 6 * q, all + 7 * q, 6 * sizeof(double));
        R->tcount[q] = (uint64_t)all[7 * q + 6];
    }
    free(all);
    R->c.st->tile_points = R->m;
done:
    free(cnt);
    free(my);
    free(smp);
    free(scnt);
    free(rcnt);
    free(pos);
    free(dst);
    free(sb);
    return s;
}
