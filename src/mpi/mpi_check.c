/* mpi_check.c -- gtet_check_mpi: the cross-rank invariants of a distributed result (the
 * local triangulations are checked by gtet_check on each rank). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/mpi_internal.h"

typedef struct creq {
    uint64_t g;        /* the tet asked about */
    uint64_t t;        /* the asking tet */
    uint64_t key[3];   /* the shared facet, sorted vertex ids */
} creq;

typedef struct crep {
    uint64_t ok;       /* 1: g has that facet and names t across it */
    uint64_t apex;
    double x[3];
} crep;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static const double *coords(const gtet_mpi_result *r, uint64_t id)
{
    const uint64_t *at = bsearch(&id, r->used_vertex_ids, r->num_used_vertices, sizeof id, cmp_u64);
    return at ? r->used_vertices + 3 * (size_t)(at - r->used_vertex_ids) : NULL;
}

/* owned tet t's vertex i and its neighbour across facet i, whatever the result's width
 * (GTET_MPI_NO_TET32 read as GTET_MPI_NO_TET) */
static uint64_t vert(const gtet_mpi_result *r, size_t t, int i)
{
    return r->id_bits == 32 ? r->tets32[4 * t + (size_t)i] : r->tets[4 * t + (size_t)i];
}

static uint64_t neigh(const gtet_mpi_result *r, size_t t, int i)
{
    if (r->id_bits != 32) return r->neighbors[4 * t + (size_t)i];
    uint32_t g = r->neighbors32[4 * t + (size_t)i];
    return g == GTET_MPI_NO_TET32 ? GTET_MPI_NO_TET : g;
}

/* owned tet t's 4 vertex ids */
static void tet_ids(const gtet_mpi_result *r, size_t t, uint64_t tv[4])
{
    for (int i = 0; i < 4; i++) tv[i] = vert(r, t, i);
}

static void facet_key(const uint64_t *tv, int f, uint64_t key[3])
{
    int j = 0;
    for (int i = 0; i < 4; i++)
        if (i != f) key[j++] = tv[i];
    for (int i = 1; i < 3; i++)
        for (int k = i; k > 0 && key[k - 1] > key[k]; k--) {
            uint64_t t = key[k];
            key[k] = key[k - 1];
            key[k - 1] = t;
        }
}

static int rank_of_tet(const gtet_mpi_result *r, int P, uint64_t g)
{
    int lo = 0, hi = P;   /* tet_offsets[lo] <= g < tet_offsets[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (r->tet_offsets[mid] <= g) lo = mid;
        else hi = mid;
    }
    return lo;
}

gtet_status gtet_check_mpi(MPI_Comm comm, const gtet_mpi_result *r, gtet_check_report *report)
{
    gtet_mpi_stats st;
    memset(&st, 0, sizeof st);
    mctx c;
    memset(&c, 0, sizeof c);
    c.comm = comm;
    c.st = &st;
    MPI_Comm_rank(comm, &c.rank);
    MPI_Comm_size(comm, &c.size);
    int P = c.size;
    gtet_check_report rep;
    memset(&rep, 0, sizeof rep);
    gtet_status s = GTET_OK;
    c.sc = mx_malloc(4 * (size_t)P * sizeof(int));
    size_t *scnt = mx_calloc((size_t)P, sizeof *scnt), *rcnt = mx_calloc((size_t)P, sizeof *rcnt);
    size_t nl = 0;
    creq *sb = NULL, *rb = NULL;
    crep *ans = NULL, *back = NULL;
    size_t *slot = NULL;
    if (!c.sc || !scnt || !rcnt || !r) s = mx_fail(&c, r ? GTET_ERR_OUT_OF_MEMORY : GTET_ERR_ARGUMENT,
                                                  "out of memory or NULL result");
    else if (r->num_tets && (r->id_bits == 32 ? !r->tets32 || !r->neighbors32
                                              : !r->tets || !r->neighbors))
        s = mx_fail(&c, GTET_ERR_ARGUMENT, "rank %d: the result has no %d-bit tets", c.rank,
                    r->id_bits == 32 ? 32 : 64);
    if (c.sc) {
        c.sd = c.sc + P;
        c.rc = c.sd + P;
        c.rd = c.rc + P;
    }
    if ((s = mx_agree(&c, s)) != GTET_OK) goto done;
    for (size_t t = 0; t < r->num_tets && s == GTET_OK; t++) {
        uint64_t tv[4];
        tet_ids(r, t, tv);
        const double *p[4];
        for (int i = 0; i < 4; i++)
            if (!(p[i] = coords(r, tv[i])))
                s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "rank %d: tet %llu uses vertex %llu, "
                            "which is not in its used vertices", c.rank,
                            (unsigned long long)(r->tet_offset + t), (unsigned long long)tv[i]);
        if (s == GTET_OK && gtet_orient3d(p[0], p[1], p[2], p[3]) <= 0)
            s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "tet %llu is not positively oriented",
                        (unsigned long long)(r->tet_offset + t));
        for (int f = 0; f < 4; f++) {
            uint64_t g = neigh(r, t, f);
            if (g == GTET_MPI_NO_TET) continue;
            if (g >= r->tet_offsets[P]) {
                s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "tet %llu: neighbour %llu out of range",
                            (unsigned long long)(r->tet_offset + t), (unsigned long long)g);
                break;
            }
            scnt[rank_of_tet(r, P, g)]++;
            nl++;
        }
    }
    sb = mx_malloc(nl * sizeof *sb);
    slot = mx_malloc(nl * sizeof *slot);
    size_t *pos = mx_calloc((size_t)P + 1, sizeof *pos);
    if (!sb || !slot || !pos) s = mx_fail(&c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(&c, s)) != GTET_OK) {
        free(pos);
        goto done;
    }
    for (int q = 0; q < P; q++) pos[q + 1] = pos[q] + scnt[q];
    for (size_t t = 0; t < r->num_tets; t++) {
        uint64_t tv[4];
        tet_ids(r, t, tv);
        for (int f = 0; f < 4; f++) {
            uint64_t g = neigh(r, t, f);
            if (g == GTET_MPI_NO_TET) continue;
            size_t k = pos[rank_of_tet(r, P, g)]++;
            sb[k].g = g;
            sb[k].t = r->tet_offset + t;
            facet_key(tv, f, sb[k].key);
            slot[k] = 4 * t + (size_t)f;
        }
    }
    free(pos);
    size_t m;
    {
        void *rr;
        if ((s = mx_exchange(&c, sb, scnt, sizeof *sb, &rr, rcnt, &m, 0)) != GTET_OK) goto done;
        rb = rr;
    }
    ans = mx_malloc(m * sizeof *ans);
    if (!ans) s = mx_fail(&c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
    if ((s = mx_agree(&c, s)) != GTET_OK) goto done;
    for (size_t k = 0; k < m; k++) {
        memset(&ans[k], 0, sizeof ans[k]);
        uint64_t lg = rb[k].g - r->tet_offset;
        if (rb[k].g < r->tet_offset || lg >= r->num_tets) continue;
        uint64_t tv[4];
        tet_ids(r, (size_t)lg, tv);
        for (int f = 0; f < 4; f++) {
            uint64_t key[3];
            facet_key(tv, f, key);
            if (memcmp(key, rb[k].key, sizeof key)) continue;
            const double *x = coords(r, tv[f]);
            if (neigh(r, (size_t)lg, f) == rb[k].t && x) {
                ans[k].ok = 1;
                ans[k].apex = tv[f];
                memcpy(ans[k].x, x, sizeof ans[k].x);
            }
        }
    }
    {
        void *rr;
        size_t tot;
        if ((s = mx_exchange(&c, ans, rcnt, sizeof *ans, &rr, scnt, &tot, 0)) != GTET_OK)
            goto done;
        back = rr;
    }
    for (size_t k = 0; k < nl && s == GTET_OK; k++) {
        size_t t = slot[k] / 4;
        int f = (int)(slot[k] % 4);
        uint64_t tv[4];
        tet_ids(r, t, tv);
        unsigned long long a = (unsigned long long)(r->tet_offset + t),
                           b = (unsigned long long)neigh(r, t, f);
        if (!back[k].ok) {
            s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "tet %llu names tet %llu across its facet "
                        "%d, which does not name it back across the same three vertices", a, b, f);
            break;
        }
        const double *p[4];
        for (int i = 0; i < 4; i++) p[i] = coords(r, tv[i]);
        const double *q[4] = {p[0], p[1], p[2], p[3]};
        q[f] = back[k].x;
        if (gtet_orient3d(q[0], q[1], q[2], q[3]) >= 0)
            s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "tets %llu and %llu are on the same side of "
                        "their shared facet", a, b);
        else if (gtet_insphere_sos(p[0], p[1], p[2], p[3], back[k].x) > 0)
            s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "the facet between tets %llu and %llu is not "
                        "locally Delaunay (perturbed): vertex %llu is inside the circumsphere "
                        "of %llu", a, b, (unsigned long long)back[k].apex, a);
    }
    if ((s = mx_agree(&c, s)) != GTET_OK) goto done;
    /* every vertex is used: the distinct used ids, counted on the rank id % P */
    {
        size_t *uc = mx_calloc((size_t)P, sizeof *uc), *ur = mx_calloc((size_t)P, sizeof *ur);
        size_t *up = mx_calloc((size_t)P + 1, sizeof *up);
        uint64_t *ub = mx_malloc((r->num_used_vertices + 1) * sizeof *ub);
        if (!uc || !ur || !up || !ub) s = mx_fail(&c, GTET_ERR_OUT_OF_MEMORY, "out of memory");
        if ((s = mx_agree(&c, s)) == GTET_OK) {
            for (size_t i = 0; i < r->num_used_vertices; i++)
                uc[r->used_vertex_ids[i] % (uint64_t)P]++;
            for (int q = 0; q < P; q++) up[q + 1] = up[q] + uc[q];
            for (size_t i = 0; i < r->num_used_vertices; i++)
                ub[up[r->used_vertex_ids[i] % (uint64_t)P]++] = r->used_vertex_ids[i];
            void *rr;
            size_t tot;
            if ((s = mx_exchange(&c, ub, uc, sizeof *ub, &rr, ur, &tot, 0)) == GTET_OK) {
                uint64_t *ids = rr;
                mpi_sort(ids, tot, sizeof *ids, cmp_u64);
                uint64_t distinct = 0, all = 0;
                for (size_t i = 0; i < tot; i++) distinct += i == 0 || ids[i] != ids[i - 1];
                free(ids);
                MPI_Allreduce(&distinct, &all, 1, MPI_UINT64_T, MPI_SUM, comm);
                if (all != r->num_vertices)
                    s = mx_fail(&c, GTET_ERR_CHECK_FAILED, "the tets use %llu of the %llu "
                                "vertices", (unsigned long long)all,
                                (unsigned long long)r->num_vertices);
            }
        }
        free(uc);
        free(ur);
        free(up);
        free(ub);
        s = mx_agree(&c, s);
    }
done:
    rep.ok = s == GTET_OK;
    rep.tets = r ? r->num_tets_global : 0;
    rep.hull_facets = r ? r->num_hull_facets : 0;
    {
        uint64_t mine = nl, all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_SUM, comm);
        rep.facets_checked = all / 2;
    }
    if (s == GTET_OK)
        snprintf(rep.message, sizeof rep.message, "check=ok tets=%llu hull_facets=%llu "
                 "interior_facets=%llu ranks=%d", (unsigned long long)rep.tets,
                 (unsigned long long)rep.hull_facets, (unsigned long long)rep.facets_checked, P);
    else
        snprintf(rep.message, sizeof rep.message, "%s", c.err.message);
    if (report) *report = rep;
    free(c.sc);
    free(scnt);
    free(rcnt);
    free(sb);
    free(rb);
    free(ans);
    free(back);
    free(slot);
    return s;
}
