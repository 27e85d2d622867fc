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

int mx_kd_rank(const run *R, const double *x)
{
    int id = 0;
    while (R->kd[id].leaf < 0)
        id = x[R->kd[id].axis] < R->kd[id].split ? R->kd[id].left : R->kd[id].right;
    return R->kd[id].leaf;
}

/* the partition's i-th point: a first occurrence (R->fp, after mx_step_dedup) or, on the
 * duplicate-free path, the caller's point with its global input index (E201) */
static void part_point(const run *R, size_t i, mpt *p)
{
    if (R->fp) {
        *p = R->fp[i];
    } else {
        memcpy(p->x, R->xyz + 3 * i, sizeof p->x);
        p->id = R->first + i;
    }
}

gtet_status mx_step_partition(run *R)
{
    mctx *c = &R->c;
    int P = c->size, me = c->rank;
    gtet_status s = GTET_OK;
    size_t S = 2048 * (size_t)P;
    if (S > ((size_t)1 << 20)) S = (size_t)1 << 20;
    /* this rank's points (nf) out of V in all: the first occurrences, or all the points */
    size_t nf = R->fp ? R->nf : R->n;
    uint64_t V = R->fp ? R->V : R->N;
    size_t mine = nf;
    if (V > S) mine = (size_t)(((uint64_t)nf * S + V - 1) / V);
    if (mine > nf) mine = nf;
    /* a second partition (after duplicates were found: mx_step_distinct) replaces the first */
    free(R->kd);
    free(R->box);
    free(R->tcount);
    int *cnt = mx_malloc(2 * (size_t)P * sizeof *cnt);
    double *my = mx_malloc((3 * mine + 1) * sizeof *my);
    R->kd = mx_malloc(2 * (size_t)P * sizeof *R->kd);
    R->box = mx_malloc(6 * (size_t)P * sizeof *R->box);
    R->tcount = mx_malloc((size_t)P * sizeof *R->tcount);
    double *smp = NULL;
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    int *dst = mx_malloc((nf + 1) * sizeof *dst);
    mpt *sb = mx_malloc((nf + 1) * sizeof *sb);
    if (!cnt || !my || !R->kd || !R->box || !R->tcount || !scnt || !rcnt || !pos || !dst || !sb)
        s = mx_fail(c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < mine; k++) {
        size_t i = (size_t)((double)k * (double)nf / (double)mine);
        mpt p;
        part_point(R, i, &p);
        memcpy(my + 3 * k, p.x, 3 * sizeof(double));
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
    for (size_t i = 0; i < nf; i++) {
        mpt p;
        part_point(R, i, &p);
        dst[i] = mx_kd_rank(R, p.x);
        scnt[dst[i]]++;
    }
    /* the points for other ranks in sb by rank; this rank's own go straight into its tile,
     * in the same order (NOTES.md E223: half the send buffer and a copy at np 2) */
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + (q == me ? 0 : scnt[q]);
    for (size_t i = 0; i < nf; i++)
        if (dst[i] != me) part_point(R, i, &sb[pos[dst[i]]++]);
    {
        void *r;
        if ((s = mx_exchange_keep(c, sb, scnt, sizeof(mpt), &r, rcnt, &R->m, 0)) != GTET_OK)
            goto done;
        R->tile = r;
        size_t at = 0;
        for (int q = 0; q < me; q++) at += rcnt[q];
        for (size_t i = 0; i < nf; i++)
            if (dst[i] == me) part_point(R, i, &R->tile[at++]);
    }
    /* no later step reads the first occurrences (dedup's path) */
    free(R->fp);
    R->fp = NULL;
    double bb[7] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY, 0};
    /* the points are finite (validated): plain comparisons, where fmin and fmax were calls
     * (NOTES.md E207) */
    for (size_t i = 0; i < R->m; i++)
        for (int k = 0; k < 3; k++) {
            double x = R->tile[i].x[k];
            bb[k] = x < bb[k] ? x : bb[k];
            bb[3 + k] = x > bb[3 + k] ? x : bb[3 + k];
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
